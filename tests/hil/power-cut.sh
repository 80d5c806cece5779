#!/bin/bash
# power-cut.sh BUILD_DIR SOURCE_DIR: the session journal against cuts where the kernel matters. The
# HIL virtual machine gets an ext4 disk (a virtio disk, cache=none, so the guest's flushes reach the
# host's disk); the kiosk replays a visitor's recording with its journal on that disk, and the VM
# is killed (SIGKILL to qemu: no shutdown, no sync) at a random moment 1.5 to 12 s into the visitor's
# session (after the kiosk took the recording's first touch).
# The next boot mounts the disk as it was left (the kernel replays ext4's journal), checks the store
# with sqlite3's integrity_check, and starts the kiosk: it must start, bring back at least every
# stroke it had reported durable ("journal: stroke N durable") on the console before the cut, and
# end with status 0 on SIGTERM. Then the next replay and cut. One line per cut, then
# "N cuts, S durable strokes checked, L lost, U unreadable stores, R restarts failed".
# Exit 0 when every check passed, 1 when one failed, 77 when this machine cannot run the VM.
#
# EMBOSS_POWERCUT_RUNS: cuts (default 3; 20 or more for the long mode). EMBOSS_POWERCUT_SEED: seeds
# the moments of the cuts (printed). EMBOSS_POWERCUT_DIR: where the disk image goes (default: the
# first of $TMPDIR, /tmp, /var/tmp and the HIL cache that takes O_DIRECT). EMBOSS_HIL_VERBOSE=1:
# echo the VM's console while it runs.
set -u -o pipefail

[ $# -ge 2 ] || { echo "usage: power-cut.sh BUILD_DIR SOURCE_DIR" >&2; exit 2; }
build=$(cd "$1" && pwd) || exit 2
src=$(cd "$2" && pwd) || exit 2
HIL_DIR="$src/tests/hil"
# shellcheck source=tests/hil/vm-lib.sh
. "$HIL_DIR/vm-lib.sh"

kiosk="$build/firmware-app/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: emboss-kiosk is not built in $build"; exit 77; }
hil_prepare || { echo "skip: this machine cannot run the HIL virtual machine"; exit 77; }
command -v mkfs.ext4 >/dev/null || hil_apt_install e2fsprogs || { echo "skip: no mkfs.ext4"; exit 77; }
# The guest runs the host's programs (chrooted into its root over 9p): sqlite3 must be here.
command -v sqlite3 >/dev/null || hil_apt_install sqlite3 || { echo "skip: no sqlite3"; exit 77; }

runs=${EMBOSS_POWERCUT_RUNS:-3}
seed=${EMBOSS_POWERCUT_SEED:-$$}
RANDOM=$seed
quiet=$([ -n "${EMBOSS_HIL_VERBOSE:-}" ] && echo 0 || echo 1)

# QEMU opens a cache=none disk with O_DIRECT, which some file systems refuse (tmpfs before Linux
# 6.6, and /tmp is a tmpfs on many machines): the image goes to the first folder that takes it.
odirect_ok() { dd if=/dev/zero of="$1/odirect-probe.$$" bs=4096 count=1 oflag=direct status=none 2>/dev/null; local rc=$?; rm -f "$1/odirect-probe.$$"; return $rc; }
work=""
for d in ${EMBOSS_POWERCUT_DIR:-} "${TMPDIR:-/tmp}" /tmp /var/tmp "$HIL_CACHE"; do
  [ -d "$d" ] && [ -w "$d" ] || continue
  w=$(mktemp -d "$d/emboss-powercut.XXXXXX") || continue
  if odirect_ok "$w"; then work=$w; break; fi
  rm -rf "$w"
done
[ -n "$work" ] || { echo "skip: no folder here takes O_DIRECT (set EMBOSS_POWERCUT_DIR)"; exit 77; }
# A qemu still running when this script is stopped is killed (its pidfile exists only while it runs).
trap '[ -s "$work/qemu.pid" ] && kill -KILL "$(cat "$work/qemu.pid")" 2>/dev/null; rm -rf "$work"' EXIT
trap 'exit 143' TERM INT
disk="$work/data.img"
truncate -s 64M "$disk" && mkfs.ext4 -q -F -L emboss-data "$disk" || { echo "FAIL: mkfs.ext4 $disk"; exit 1; }

# The kiosk as kiosk_crash.sh runs it, its journal on the VM's disk, with two differences for the
# emulated CPU. idle_seconds = 3600: a start restores a session left less than idle_seconds ago and
# closes one left longer (docs/sessions.md), and under emulation the next start can come more than
# the default 60 s after the cut. --attract-start=0:0: a kiosk that has just started shows its first
# piece a third done, some 450 operations built before the first frame, 35-40 s under emulation,
# while the recording's events queue up and then come in at once; from a bare sheet the first frame
# takes a few seconds and the strokes are made and committed one after another, as on the kiosk.
mnt=/run/emboss-data
common=(--config /tmp/powercut.conf --display=headless --size 160x100 --threads 1 --sessions-dir "$mnt/sessions"
  --pieces "$src/firmware-app/pieces" --attract-start=0:0 --log-level=debug)
demo="$src/tests/app/data/visitor-demo.events"

# The guest's part of one boot: PC_RESTART=1 checks what the last cut left (integrity of the store as
# the cut left it, on a copy so that the kiosk reads it untouched; the kiosk started, then ended with
# SIGTERM; integrity of the store after it); PC_REPLAY=1 then replays the recording with the kiosk's
# log on the console until the host kills the VM. Markers: "EMBOSS-POWERCUT what ...". This is
# sourced by the VM's /init (busybox sh): it must not exit.
guest_body() {
  cat <<'EOF'
pc_mark() { echo "EMBOSS-POWERCUT $*"; }
pc_integrity() { hil_chroot sqlite3 "$1" 'PRAGMA integrity_check' 2>&1 | head -5 | tr '\n' ' ' | sed 's/ *$//'; }
pc_restart_check() {
  local db="$R$PC_MNT/sessions/sessions.db" log=$R/tmp/pc-restart.err pid i rc
  rm -rf $R/tmp/pc-copy && mkdir -p $R/tmp/pc-copy
  if [ -e "$db" ]; then
    cp "$db" "$R/tmp/pc-copy/" && for f in "$db-wal" "$db-shm"; do [ -e "$f" ] && cp "$f" "$R/tmp/pc-copy/"; done
    pc_mark "integrity-as-cut $(pc_integrity /tmp/pc-copy/sessions.db)"
  else
    pc_mark "integrity-as-cut no-store"
  fi
  ( pc_kiosk_restart ) > /dev/null 2> "$log" &
  pid=$!
  i=0
  while [ $i -lt 300 ] && kill -0 $pid 2>/dev/null && ! grep -q 'first frame on the screen' "$log"; do sleep 1; i=$((i + 1)); done
  if grep -q 'first frame on the screen' "$log"; then pc_mark "restart-ready $i"; else pc_mark "restart-not-ready $i"; fi
  kill -TERM $pid 2>/dev/null
  i=0
  while [ $i -lt 60 ] && kill -0 $pid 2>/dev/null; do sleep 1; i=$((i + 1)); done
  kill -0 $pid 2>/dev/null && { pc_mark "restart-hung"; kill -KILL $pid; }
  wait $pid; rc=$?
  sed 's/^/EMBOSS-POWERCUT-LOG /' "$log"
  pc_mark "restart-rc $rc"
  pc_mark "moved-aside $(ls "$R$PC_MNT/sessions" | grep -c corrupt)"
  pc_mark "integrity-after $(pc_integrity "$PC_MNT/sessions/sessions.db")"
}

hil_modprobe virtio_blk ext4
i=0
while [ ! -b /dev/vda ] && [ $i -lt 100 ]; do usleep 100000; i=$((i + 1)); done
mkdir -p "$R$PC_MNT"
if mount -t ext4 /dev/vda "$R$PC_MNT"; then
  pc_mark "mounted $(grep " $R$PC_MNT " /proc/mounts | cut -d' ' -f4); write cache: $(cat /sys/block/vda/queue/write_cache)"
  printf 'idle_seconds = 3600\n' > $R/tmp/powercut.conf
  [ "$PC_RESTART" = 1 ] && pc_restart_check
  if [ "$PC_REPLAY" = 1 ]; then
    pc_mark "replay"
    pc_kiosk_replay 2>&1
    pc_mark "replay-ended $?"
  fi
  umount "$R$PC_MNT" && pc_mark "unmounted"
else
  pc_mark "mount-failed $(dmesg | tail -3 | tr "\n" " ")"
fi
EOF
}

# One boot: writes its job, boots, and when $2 is 1 kills qemu $3 ms after the visitor arrived.
# Sets boot_console, boot_secs, cut_at (seconds from boot to the cut, empty when there was none).
boot() {
  local restart=$1 replay=$2 ms=$3 job="$work/job.sh" pidfile="$work/qemu.pid" t0 bootpid
  boot_console="$work/console.$boots"
  {
    printf 'PC_MNT=%q\nPC_RESTART=%d\nPC_REPLAY=%d\n' "$mnt" "$restart" "$replay"
    # ( pc_kiosk_restart ) & is the kiosk's own pid: the subshell execs it (through hil-chroot's execs).
    printf 'pc_kiosk_restart() { exec /bin/hil-chroot'; printf ' %q' "$kiosk" "${common[@]}" --tablet=none; printf '; }\n'
    printf 'pc_kiosk_replay() { /bin/hil-chroot'; printf ' %q' "$kiosk" "${common[@]}" "--tablet=evemu:$demo"; printf '; }\n'
    guest_body
  } > "$job"
  rm -f "$pidfile"
  # shellcheck disable=SC2034  # read by hil_boot
  HIL_QEMU_EXTRA=(-drive "file=$disk,format=raw,if=virtio,cache=none" -pidfile "$pidfile")
  t0=$(date +%s.%N)
  # Its stderr aside: bash reports the qemu killed there ("Killed timeout ... qemu ...").
  hil_boot "$job" "${EMBOSS_POWERCUT_BOOT_TIMEOUT:-600}" "$boot_console" "$quiet" 2> "$work/boot.err" &
  bootpid=$!
  cut_at=""
  if [ "$replay" = 1 ]; then
    # From the first touch the kiosk takes (the recording touches 0.3 s in) strokes are made.
    while kill -0 $bootpid 2>/dev/null && ! grep -qa '^emboss-kiosk: state: visitor-arrived' "$boot_console" 2>/dev/null; do sleep 0.1; done
    if kill -0 $bootpid 2>/dev/null && [ -s "$pidfile" ]; then
      sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
      if grep -qa '^EMBOSS-POWERCUT replay-ended' "$boot_console"; then
        : # the kiosk stopped by itself: reported by the caller
      elif kill -KILL "$(cat "$pidfile")" 2>/dev/null; then
        cut_at=$(echo "$t0 $(date +%s.%N)" | awk '{printf "%.1f", $2 - $1}')
      fi
    fi
  fi
  wait $bootpid
  boot_rc=$?
  rm -f "$pidfile"
  boot_secs=$(echo "$t0 $(date +%s.%N)" | awk '{printf "%.0f", $2 - $1}')
}

marker() { sed -n "s/^EMBOSS-POWERCUT $1 //p" "$boot_console" | tail -1; }
# Every durable line qemu passed on before it died counts: the guest wrote it to the console after
# the journal's commit had returned, so the stroke was on the (virtual) disk before the cut. Lines
# still in the guest's serial buffer at the cut never reach the host and are not counted.
durable_in() { awk '$0 == "EMBOSS-POWERCUT replay" {on = 1} on' "$1" | sed -n 's/^emboss-kiosk: journal: stroke \([0-9]*\) durable$/\1/p' | sort -n | tail -1; }
restored_in() { sed -n 's/^EMBOSS-POWERCUT-LOG .*session: restored session [0-9]*: \([0-9]*\) strokes.*/\1/p' "$1" | tail -1; }
show_console() {
  echo "--- the VM's console (last lines)"; grep -av '^emboss-kiosk: journal: stroke' "$boot_console" | tail -25
  grep -v 'Killed.*timeout' "$work/boot.err"; echo "---"
}

echo "power cut: $runs cuts, seed $seed, disk $disk (64 MiB ext4, virtio, cache=none)"
fail=0 cuts=0 checked=0 lost=0 unreadable=0 restarts_failed=0
boots=0 want=0 prev_ms=0 prev_cut=""
t_start=$SECONDS
for i in $(seq 1 $((runs + 1))); do
  boots=$i
  restart=$([ "$i" -gt 1 ] && echo 1 || echo 0)
  replay=$([ "$i" -le "$runs" ] && echo 1 || echo 0)
  ms=$((1500 + RANDOM % 10500))
  boot "$restart" "$replay" "$ms"
  [ "$i" = 1 ] && echo "disk in the VM: $(marker mounted)"
  if [ -z "$(marker mounted)" ]; then
    echo "FAIL boot $i: the disk was not mounted ($(marker mount-failed))"; show_console; fail=1; break
  fi
  case "$(marker mounted)" in *"write cache: write back") ;; *)
    echo "FAIL boot $i: the guest does not see a write-back cache, so it sends no flushes: $(marker mounted)"; fail=1 ;;
  esac
  # What the last cut left.
  if [ "$restart" = 1 ]; then
    got=$(restored_in "$boot_console"); got=${got:-0}
    rc=$(marker restart-rc) as_cut=$(marker integrity-as-cut) after=$(marker integrity-after) aside=$(marker moved-aside)
    damaged=$(grep -ac '^EMBOSS-POWERCUT-LOG .*\(damaged\|dropped\|moved aside\)' "$boot_console")
    problems=""
    if [ -z "$(marker restart-ready)" ] || [ "$rc" != 0 ]; then
      restarts_failed=$((restarts_failed + 1)); problems+=" the restart failed (ready: $(marker restart-ready)$(marker restart-not-ready), exit ${rc:-none});"
    fi
    if [ "$got" -lt "$want" ]; then lost=$((lost + want - got)); problems+=" $((want - got)) durable strokes lost;"; fi
    # No store at all is right only when the cut came before the kiosk had made one durable stroke.
    sound=1
    case "$as_cut" in ok) ;; no-store) [ "$want" = 0 ] || sound=0 ;; *) sound=0 ;; esac
    [ "$after" = ok ] && [ "$aside" = 0 ] && [ "$damaged" = 0 ] || sound=0
    if [ $sound = 0 ]; then
      unreadable=$((unreadable + 1)); problems+=" the store is damaged (as cut: $as_cut; after: $after; moved aside: $aside; damage reports: $damaged);"
    fi
    checked=$((checked + want))
    line="cut $((i - 1)): killed ${prev_ms} ms after the first touch ($prev_cut s after boot), $want durable, $got restored, integrity $as_cut/$after, restart ready in $(marker restart-ready) s"
    if [ -n "$problems" ]; then echo "FAIL $line:$problems"; show_console; fail=1; else echo "ok   $line"; fi
  fi
  [ "$replay" = 1 ] || break
  # This boot's replay and cut.
  if [ -z "$cut_at" ]; then
    ended=$(marker replay-ended)
    echo "FAIL boot $i: no cut (the replay $([ -n "$ended" ] && echo "ended by itself, exit $ended" || echo "did not start"); VM status $boot_rc after $boot_secs s)"
    show_console; fail=1; break
  fi
  cuts=$((cuts + 1))
  want=$(durable_in "$boot_console"); want=${want:-0}
  prev_ms=$ms prev_cut=$cut_at
done
if [ "$boots" = $((runs + 1)) ] && ! grep -qa "^EMBOSS-POWERCUT unmounted" "$boot_console"; then echo "FAIL the last boot did not unmount the disk"; show_console; fail=1; fi
# After the last boot's clean unmount the file system must be clean.
if fsck_out=$(e2fsck -fn "$disk" 2>&1); then echo "ok   e2fsck -fn: clean"; else echo "FAIL e2fsck -fn:"; echo "$fsck_out" | tail -10; fail=1; fi
echo "time: $((SECONDS - t_start)) s for $boots boots ($(( (SECONDS - t_start) / boots )) s a boot)"
echo "$cuts cuts, $checked durable strokes checked, $lost lost, $unreadable unreadable stores, $restarts_failed restarts failed (seed $seed)"
[ "$cuts" = "$runs" ] && [ $lost = 0 ] && [ $unreadable = 0 ] && [ $restarts_failed = 0 ] || fail=1
exit $fail

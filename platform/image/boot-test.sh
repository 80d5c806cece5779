#!/bin/bash
# boot-test.sh: boots the kiosk appliance's amd64 image in QEMU (software emulation) and checks it as a
# visitor, staff and a power cut would: systemd as PID 1 on the image's own root, the kiosk's unit,
# its screen, a pen, the watchdog, a staff export onto a USB stick, a hard power-off.
#
#   platform/image/boot-test.sh IMAGE_OR_BUILD_DIR
#     IMAGE            an emboss-amd64.img made by build-image.sh (tested as it is, on a copy)
#     BUILD_DIR        a CMake build tree: the image is built first from BUILD_DIR/deb/package/emboss_*.deb
#                      (the CTest test appliance.deb makes it), else make-deb.sh BUILD_DIR/deb makes it
#   EMBOSS_IMAGE_DEB=FILE   build with this .deb instead
#   EMBOSS_BUILD_DIR=DIR    where the pen helper (tests/hil/uinput_play) is built (default: BUILD_DIR,
#                           else the checkout's build/)
#   EMBOSS_FIXTURES=DIR     the fixtures (default: ../shared/fixtures beside the checkout)
#   EMBOSS_BOOT_TEST_VERBOSE=1  echo the guest's serial console at the end
#   EMBOSS_BOOT_TEST_KEEP=DIR   keep the consoles, the guest's journals and the screendumps there
# Exit codes: 0 every check passed, 1 a check failed, 2 bad usage, 77 cannot run here (no qemu and
# not root to install it, no fixtures, no image and none can be built).
#
# The copy under test gets a test-only layer, written into its root file system with debugfs (the
# shipped image has none of it): an agent unit that runs the test's commands from a virtio serial
# port, the pen helper and a tablet recording. The agent is started by systemd.wants= on the kernel
# command line; the rest of the command line is the image's own boot entry (read from its EFI
# partition), plus console=ttyS0. QEMU boots the image's kernel and initrd directly (-kernel), so the
# test does not depend on firmware; the image's systemd-boot is for real PCs (README.md).
# The display is QEMU's bochs-display at 320x200 (the kiosk takes the screen's preferred mode; a
# small one keeps the software-emulated first frame short). Nothing of the kiosk's unit is changed:
# the watchdog is the shipped WatchdogSec.
set -u -o pipefail
trap '' PIPE

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
src=$(cd "$here/../.." && pwd)
[ $# -eq 1 ] || { sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
target=$1

say() { echo "boot-test: $*" >&2; }
skip() { say "$* -- skipped"; exit 77; }

# ---- tools
need=()
command -v qemu-system-x86_64 >/dev/null || need+=(qemu-system-x86)
command -v mcopy >/dev/null || need+=(mtools)
command -v mkfs.vfat >/dev/null || need+=(dosfstools)
command -v debugfs >/dev/null || need+=(e2fsprogs)
command -v sfdisk >/dev/null || need+=(fdisk)
if [ ${#need[@]} -gt 0 ]; then
  [ "$(id -u)" = 0 ] || skip "need ${need[*]} and not root to install them"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1 ||
    { apt-get update -qq >/dev/null 2>&1; DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null 2>&1; } ||
    skip "apt-get install ${need[*]} failed"
fi

# ---- fixtures: a real tablet recording for the pen, one where the pen touches the tablet and drags
# (a recording of a pen only hovering makes no stroke, and rightly so)
fixtures=${EMBOSS_FIXTURES:-$src/../shared/fixtures}
events="$fixtures/evemu/Wacom Intuos4 6x9.stylus-drag.events"
desc="$fixtures/evemu/Wacom Intuos4 6x9 Pen.desc"
[ -f "$events" ] && [ -f "$desc" ] || skip "no tablet recording at $events (set EMBOSS_FIXTURES)"

# ---- the image
if [ -f "$target" ]; then
  image=$(readlink -f "$target")
  build=${EMBOSS_BUILD_DIR:-$src/build}
else
  build=$(cd "$target" && pwd) || exit 2
  args=(-o "$build/image")
  deb=${EMBOSS_IMAGE_DEB:-$(ls -t "$build"/deb/package/emboss_*.deb 2>/dev/null | head -1)}
  if [ -n "$deb" ]; then args+=(--deb "$deb"); else args+=(--build-dir "$build/deb"); fi
  t0=$SECONDS
  image=$(bash "$here/build-image.sh" "${args[@]}" | tail -1)
  rc=$?
  [ $rc -eq 77 ] && skip "build-image.sh cannot build the image here"
  [ $rc -eq 0 ] && [ -f "$image" ] || { say "build-image.sh failed ($rc)"; exit 1; }
  say "image ready in $((SECONDS - t0)) s: $image"
fi
build=${EMBOSS_BUILD_DIR:-$build}
# The pen and button helpers, built against the build tree like the HIL test programs.
bash "$src/tests/hil/build.sh" "$build" "$src" uinput_play cp2112_buttons >&2 || skip "cannot build tests/hil/uinput_play and cp2112_buttons in $build"
play="$build/hil/uinput_play"

# ---- a copy of the image with the test layer
cache=${EMBOSS_IMAGE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/emboss-image}
mkdir -p "$cache/jobs" || exit 77
job=$(mktemp -d "$cache/jobs/boot.XXXXXX")
qpid=""
cleanup() {
  [ -n "$qpid" ] && kill "$qpid" 2>/dev/null
  # EMBOSS_BOOT_TEST_KEEP=DIR keeps the consoles, the guest's journals and the screendumps.
  [ -n "${EMBOSS_BOOT_TEST_KEEP:-}" ] && mkdir -p "$EMBOSS_BOOT_TEST_KEEP" &&
    cp "$job"/*.log "$job"/*.ppm "$EMBOSS_BOOT_TEST_KEEP"/ 2>/dev/null
  exec 6>&- 7>&- 2>/dev/null
  wait 2>/dev/null
  rm -rf "$job"
}
trap cleanup EXIT
disk="$job/disk.img"
cp --sparse=always "$image" "$disk" || { say "cannot copy $image"; exit 1; }
part_start() {  # part_start NAME|NUMBER: the partition's first sector
  sfdisk -d "$disk" 2>/dev/null | awk -v want="$1" -F'[:,]' '
    $1 ~ /^\// { n++; start = ""; name = ""
      for (i = 2; i <= NF; i++) { if ($i ~ /start=/) { start = $i; gsub(/[^0-9]/, "", start) } if ($i ~ /name=/) { name = $i; sub(/.*name="?/, "", name); sub(/".*/, "", name) } }
      if (name == want || n == want) print start }'
}
esp=$(part_start 1) root=$(part_start emboss-root)
[ -n "$esp" ] && [ -n "$root" ] || { say "$image has no EFI and emboss-root partitions"; exit 1; }
export MTOOLS_SKIP_CHECK=1
mcopy -n -i "$disk@@$((esp * 512))" ::/emboss/vmlinuz "$job/vmlinuz" &&
  mcopy -n -i "$disk@@$((esp * 512))" ::/emboss/initrd.img "$job/initrd.img" &&
  mcopy -n -i "$disk@@$((esp * 512))" ::/loader/entries/emboss.conf "$job/entry.conf" || { say "no kernel or boot entry on the EFI partition"; exit 1; }
cmdline=$(sed -n 's/^options //p' "$job/entry.conf")
[ -n "$cmdline" ] || { say "the boot entry has no options line"; exit 1; }
layer="$here/test-layer"
dd if="$disk" of="$job/root.ext4" bs=512 skip="$root" count="$(sfdisk -d "$disk" | awk -F'size= *' '/name="emboss-root"/ {split($2, a, ","); print a[1]}')" conv=sparse status=none
# The kiosk's staff buttons: a test-only drop-in adds --buttons= to the shipped command line (a PC
# has no GPIO header for the built-in wiring).
exec_start=$(for f in /lib/systemd/system/emboss-kiosk.service /usr/lib/systemd/system/emboss-kiosk.service; do
  debugfs -R "cat $f" "$job/root.ext4" 2>/dev/null; done | sed -n 's/^ExecStart=//p' | head -1)
[ -n "$exec_start" ] || { say "the image has no emboss-kiosk.service with an ExecStart="; exit 1; }
# --log-level=debug: the journal's "journal: stroke N durable" lines, which the power cut checks.
printf '# Test only (boot-test.sh): the staff buttons on the emulated CP2112; the durable strokes logged.\n[Service]\nExecStart=\nExecStart=%s --buttons=/usr/local/lib/emboss-test/buttons.json --log-level=debug\n' "$exec_start" > "$job/buttons.conf"
debugfs -w -f - "$job/root.ext4" > "$job/debugfs.log" 2>&1 <<EOF
mkdir /usr/local/lib/emboss-test
write "$layer/agent.sh" /usr/local/lib/emboss-test/agent.sh
sif /usr/local/lib/emboss-test/agent.sh mode 0100755
write "$play" /usr/local/lib/emboss-test/uinput_play
sif /usr/local/lib/emboss-test/uinput_play mode 0100755
write "$events" /usr/local/lib/emboss-test/pen.events
write "$desc" /usr/local/lib/emboss-test/pen.desc
write "$build/hil/cp2112_buttons" /usr/local/lib/emboss-test/cp2112_buttons
sif /usr/local/lib/emboss-test/cp2112_buttons mode 0100755
write "$layer/buttons.json" /usr/local/lib/emboss-test/buttons.json
write "$layer/emboss-test-agent.service" /etc/systemd/system/emboss-test-agent.service
mkdir /etc/systemd/system/emboss-kiosk.service.d
write "$job/buttons.conf" /etc/systemd/system/emboss-kiosk.service.d/emboss-test-buttons.conf
EOF
debugfs -R 'ls -l /usr/local/lib/emboss-test' "$job/root.ext4" 2>/dev/null | grep -q uinput_play || { cat "$job/debugfs.log" >&2; say "cannot write the test layer"; exit 1; }
dd if="$job/root.ext4" of="$disk" bs=512 seek="$root" conv=notrunc,sparse status=none && rm -f "$job/root.ext4"

# The USB stick: FAT, as staff would bring one.
truncate -s 64M "$job/stick.img" && mkfs.vfat -n EMBOSSUSB "$job/stick.img" >/dev/null || { say "cannot make the stick image"; exit 1; }

# ---- the VM: agent and monitor over pipes, the serial console into a file
accel=tcg
boot_n=0
boot() {
  boot_n=$((boot_n + 1))
  rm -f "$job"/agent.{in,out} "$job"/mon.{in,out}
  mkfifo "$job/agent.in" "$job/agent.out" "$job/mon.in" "$job/mon.out"
  : > "$job/agent.log"
  timeout -k 5 900 qemu-system-x86_64 -nodefaults -no-user-config -display none -no-reboot \
    -machine q35 -cpu max -smp 2 -m 1536 -accel tcg,thread=multi,tb-size=256 \
    -kernel "$job/vmlinuz" -initrd "$job/initrd.img" \
    -append "$cmdline console=ttyS0 systemd.wants=emboss-test-agent.service" \
    -drive "file=$disk,format=raw,if=virtio" \
    -device bochs-display,xres=320,yres=200 \
    -device qemu-xhci,id=xhci -drive "if=none,id=stick,file=$job/stick.img,format=raw" -device usb-storage,bus=xhci.0,drive=stick \
    -device virtio-serial-pci -chardev "pipe,id=agent,path=$job/agent" -device virtserialport,chardev=agent,name=emboss.agent \
    -chardev "pipe,id=mon,path=$job/mon" -mon chardev=mon,mode=readline \
    -serial "file:$job/console-$boot_n.log" -nic none < /dev/null > "$job/qemu-$boot_n.log" 2>&1 &
  qpid=$!
  cat "$job/agent.out" >> "$job/agent.log" &
  cat "$job/mon.out" > "$job/mon-$boot_n.log" &
  exec 6> "$job/agent.in" 7> "$job/mon.in"
  boot_t0=$SECONDS
}
# agent TIMEOUT COMMAND: runs COMMAND in the guest; its output on stdout, its status as ours
# (124 when no answer came in TIMEOUT seconds).
agent() {
  local limit=$1 id
  shift
  id="c$(date +%s%N)"  # unique even from the subshells of $(agent ...)
  printf '%s %s %s\n' "$id" "$limit" "$(printf '%s' "$*" | base64 -w0)" >&6 || return 124
  local end=$((SECONDS + limit)) line
  while [ $SECONDS -lt $end ]; do
    line=$(grep -a "^EMBOSS-AGENT-END $id " "$job/agent.log")
    if [ -n "$line" ]; then
      grep -a "^$id| " "$job/agent.log" | cut -c$((${#id} + 3))-
      return "${line##*rc=}"
    fi
    sleep 0.3
  done
  return 124
}
wait_agent() {  # the agent's hello of this boot
  local end=$((SECONDS + $1))
  while [ $SECONDS -lt $end ]; do
    [ "$(grep -ac '^EMBOSS-AGENT-READY' "$job/agent.log")" -ge 1 ] && return 0
    kill -0 "$qpid" 2>/dev/null || return 1
    sleep 1
  done
  return 1
}
screendump() {  # screendump: a PPM of the screen now; prints its path
  local f="$job/shot-$(date +%s%N).ppm"  # unique even from the subshells of $(screendump)
  echo "screendump $f" >&7
  local end=$((SECONDS + 20)) size=-1
  while [ $SECONDS -lt $end ]; do
    if [ -s "$f" ] && [ "$(stat -c %s "$f")" = "$size" ]; then break; fi
    [ -f "$f" ] && size=$(stat -c %s "$f")
    sleep 0.5
  done
  echo "$f"
}
lit() { tail -c +16 "$1" 2>/dev/null | tr -d '\000' | wc -c; }  # bytes of the picture that are not black

# ---- the table
fails=0
results=()
check() {  # check NAME OK(0|1) DETAIL
  local mark=PASS
  [ "$2" = 0 ] || { mark=FAIL; fails=$((fails + 1)); }
  results+=("$(printf '%-4s  %-34s %s' "$mark" "$1" "$3")")
  say "$mark $1: $3"
  # A failure shows the kiosk's last lines (all its runs this boot), to find the cause from the log.
  [ "$mark" = PASS ] || agent 20 "journalctl -b -u emboss-kiosk -o short-monotonic --no-pager | tail -12
    journalctl -b -u 'emboss-test-*' -o short-monotonic --no-pager | tail -6" | sed 's/^/boot-test:   | /' >&2
}
# The kiosk's log of its current invocation (the unit restarts it during the test), in the guest.
KJ='journalctl -b -o cat _SYSTEMD_INVOCATION_ID=$(systemctl show -p InvocationID --value emboss-kiosk)'
show() { agent 30 "systemctl show -p ActiveState,SubState,NRestarts,MainPID,Result emboss-kiosk.service | tr '\n' ' '"; }
prop() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }
wait_active() {  # wait_active SECONDS: the unit active and running (READY=1 received); prints the properties
  local end=$((SECONDS + $1)) s
  while [ $SECONDS -lt $end ]; do
    s=$(show)
    [ "$(prop "$s" ActiveState)" = active ] && [ "$(prop "$s" SubState)" = running ] && { echo "$s"; return 0; }
    sleep 2
  done
  echo "$s"
  return 1
}
# Seconds from the kiosk process's start (this invocation) to its 'first frame on the screen' line.
first_frame_wait() {  # first_frame_wait SECONDS: waits for this invocation's first frame; prints the line
  agent $(($1 + 10)) "e=\$((SECONDS + $1)); while [ \$SECONDS -lt \$e ]; do
      id=\$(systemctl show -p InvocationID --value emboss-kiosk)
      l=\$(journalctl -b -o short-monotonic _SYSTEMD_INVOCATION_ID=\$id 2>/dev/null | grep -m1 'first frame on the screen') && { echo \"\$l\"; exit 0; }
      sleep 0.5; done; exit 1"
}

# A failed run's consoles, journals and screendumps are kept outside the checkout (the newest 10),
# so that a failure in a run nobody watched (CI, a clone since removed) can be read afterwards.
kept=""
keep_failure() {
  kept="$cache/failures/$(date +%Y%m%d-%H%M%S)-$$"
  mkdir -p "$kept" && cp "$job"/*.log "$job"/*.ppm "$kept"/ 2>/dev/null
  printf '%s\n' "${results[@]}" > "$kept/results.txt"
  ls -1d "$cache"/failures/*/ 2>/dev/null | sort | head -n -10 | xargs -r rm -rf
}

t_all=$SECONDS
say "booting $(basename "$image") (software emulation; a few minutes)"
boot
if ! wait_agent 300; then
  check "boot: the test agent answers" 1 "no answer within 300 s (console: $(tail -c 300 "$job/console-1.log" | tr '\n' ' '))"
  [ "${EMBOSS_BOOT_TEST_VERBOSE:-0}" = 1 ] && cat "$job/console-1.log" >&2
  keep_failure
  printf '%s\n' "${results[@]}"
  echo "the logs are kept in $kept"
  exit 1
fi
check "boot: systemd is PID 1" "$([ "$(agent 20 'readlink /proc/1/exe')" = /usr/lib/systemd/systemd ] && echo 0 || echo 1)" \
  "$(agent 20 'readlink /proc/1/exe; findmnt -no OPTIONS / | cut -d, -f1' | tr '\n' ' ')(root mount options first)"

# 1. The unit: active means READY=1 came (Type=notify, NotifyAccess=main: only the kiosk's own process can send it).
s=$(wait_active 240); ok=$?
pid=$(prop "$s" MainPID)
check "unit active (READY=1 from the kiosk)" $ok "$s"
ff=$(first_frame_wait 150)
check "kiosk: first frame on the screen" "$([ -n "$ff" ] && echo 0 || echo 1)" "${ff:-none within 150 s}"
ff_boot1=$(echo "$ff" | sed -n 's/^\[ *\([0-9.]*\)\].*/\1/p')
user=$(agent 20 "stat -c %U /proc/$pid")
check "kiosk runs as emboss-kiosk" "$([ "$user" = emboss-kiosk ] && echo 0 || echo 1)" "user of PID $pid: ${user:-?}"
# (An fd the kiosk closes between ls's listing and its look at it, a file read and closed, is
# gone, not held: ls's complaint about it is no device.)
devs=$(agent 20 "ls -l /proc/$pid/fd 2>/dev/null | sed -n 's:.* -> \\(/dev/.*\\):\\1:p' | sort -u | tr '\n' ' '")
bad=$(echo "$devs" | tr ' ' '\n' | grep -v '^$' | grep -Ev '^/dev/(null|dri/card[0-9]+|dri/renderD[0-9]+|input/event[0-9]+|hidraw[0-9]+|bus/usb/.*|gpiochip[0-9]+|video[0-9]+)$')
check "kiosk holds only its devices" "$([ -z "$bad" ] && echo "$devs" | grep -q '/dev/dri/' && echo 0 || echo 1)" \
  "open: ${devs:-none}${bad:+; not its own: $bad}"
# The cgroup's device policy, tried from inside the kiosk's cgroup: the disk refused, the GPU allowed.
pol=$(agent 20 "systemctl show -p DevicePolicy --value emboss-kiosk; cg=/sys/fs/cgroup\$(systemctl show -p ControlGroup --value emboss-kiosk)
  sh -c \"echo \\\$\\\$ > \$cg/cgroup.procs; head -c1 /dev/vda > /dev/null 2>&1 && echo disk:open || echo disk:refused; exec 3< /dev/dri/card0 && echo gpu:open || echo gpu:refused\"")
check "cgroup device policy" "$(echo "$pol" | tr '\n' ' ' | grep -q '^closed disk:refused gpu:open' && echo 0 || echo 1)" "$(echo "$pol" | tr '\n' ' ')(a process in the kiosk's cgroup, as root)"

# 2. The screen: attract mode moves.
a=$(screendump); sleep 4; b=$(screendump)
check "screen: attract mode moves" "$([ "$(lit "$a")" -gt 1000 ] && ! cmp -s "$a" "$b" && echo 0 || echo 1)" \
  "two screendumps 4 s apart $(cmp -s "$a" "$b" && echo equal || echo differ); $(lit "$a") non-black bytes"

# 3. A pen: a uinput tablet replaying the recording; the kiosk takes it and leaves attract mode.
agent 20 "modprobe uinput; systemd-run --quiet --unit=emboss-test-pen /usr/local/lib/emboss-test/uinput_play /usr/local/lib/emboss-test/pen.events --before 6 --frame 0 --after 3" > /dev/null
st=$(agent 60 "e=\$((SECONDS + 50)); while [ \$SECONDS -lt \$e ]; do $KJ | grep -m1 'state: visitor-arrived' && exit 0; sleep 0.5; done; exit 1")
agent 60 "while systemctl is-active -q emboss-test-pen; do sleep 0.5; done" > /dev/null
sleep 3
c=$(screendump); sleep 3; d=$(screendump)
tab=$(agent 20 "$KJ | grep '^\(emboss-kiosk: \)\{0,1\}tablet: ' | grep -v 'no tablet\|looking again\|without a pen' | head -1")
check "pen: the kiosk takes the tablet" "$([ -n "$tab" ] && echo 0 || echo 1)" "${tab:-no 'tablet:' line}"
check "pen: leaves attract mode" "$([ -n "$st" ] && echo 0 || echo 1)" "${st:-no 'state: visitor-arrived' line}"
check "screen: the stroke shows" "$(! cmp -s "$b" "$c" && cmp -s "$c" "$d" && echo 0 || echo 1)" \
  "after the replay the screen $(cmp -s "$b" "$c" && echo 'is attract mode still' || echo 'changed from attract mode') and $(cmp -s "$c" "$d" && echo 'holds still (the bench)' || echo 'still moves')"

# 4. Staff export onto the USB stick, through the kiosk's staff menu: the staff buttons on a GPIO
# chip (a CP2112 USB GPIO bridge emulated over uhid; the test's buttons.json): staff (line 0), down
# the menu to "Export sessions" (1), choose (2), back to the exhibit (3).
gp=$(agent 30 "modprobe uhid; modprobe hid-cp2112; mkfifo /run/emboss-test-buttons
  systemd-run --quiet --unit=emboss-test-buttons /usr/local/lib/emboss-test/cp2112_buttons /run/emboss-test-buttons
  e=\$((SECONDS + 30)); while [ \$SECONDS -lt \$e ]; do l=\$($KJ | grep -m1 'buttons: back') && { echo \"\$l\"; exit 0; }; sleep 0.5; done; exit 1")
check "staff: the kiosk opens the buttons" $? "${gp:-no 'buttons: back' line}"
press() { agent 20 "echo 'press $1 0.4' > /run/emboss-test-buttons; sleep 1.5" > /dev/null; }
press 0; press 1; press 2
ex=$(agent 90 "e=\$((SECONDS + 80)); while [ \$SECONDS -lt \$e ]; do l=\$($KJ | grep -m1 'staff: .*\(Exported\|export done\|export failed\|[Nn]o stick\|cannot\)') && { echo \"\$l\"; exit 0; }; sleep 0.5; done; exit 1")
press 3
agent 30 "sync; for u in \$(systemctl list-units --plain --no-legend 'emboss-export-mount@*' | cut -d' ' -f1); do systemctl stop \$u; done" > /dev/null
files=$(mdir -i "$job/stick.img" -/ -b :: 2>/dev/null | grep -c '\.json$')
one=$(mdir -i "$job/stick.img" -/ -b :: 2>/dev/null | grep '\.json$' | head -1)
[ -n "$one" ] && mcopy -n -i "$job/stick.img" "$one" "$job/exported.json" 2>/dev/null
check "staff export reaches the USB stick" "$(echo "$ex" | grep -q 'Exported\|export done' && [ "$files" -gt 0 ] && grep -q '"operations"' "$job/exported.json" 2>/dev/null && echo 0 || echo 1)" \
  "${ex:-no staff line}; on the stick (mtools): $files .json files${one:+, ${one#::}}"

# 5. The watchdog: a stopped kiosk is killed and started again by systemd.
wd=$(agent 20 "systemctl show -p WatchdogUSec --value emboss-kiosk")
s=$(show); pid=$(prop "$s" MainPID); nr=$(prop "$s" NRestarts)
r=$(agent 120 "t0=\$(cut -d' ' -f1 /proc/uptime); kill -STOP $pid
  e=\$((SECONDS + 100)); while [ \$SECONDS -lt \$e ]; do p=\$(systemctl show -p MainPID --value emboss-kiosk); [ \"\$p\" != $pid ] && [ \"\$p\" != 0 ] && break; sleep 0.5; done
  t1=\$(cut -d' ' -f1 /proc/uptime); echo \"\$p \$(awk \"BEGIN{print \$t1 - \$t0}\")\"")
newpid=${r%% *}; took=${r##* }
wd_s=$(echo "$wd" | sed -n 's/^\([0-9]*\)s$/\1/p')
wdlog=$(agent 20 "journalctl -b -u emboss-kiosk -o cat | grep -m1 -i 'watchdog timeout'")
check "watchdog: SIGSTOP -> restarted" "$([ -n "$newpid" ] && [ "$newpid" != "$pid" ] && [ -n "$wdlog" ] && [ -n "$wd_s" ] && awk -v t="$took" -v w="$wd_s" 'BEGIN{exit !(t <= w + 15)}' && echo 0 || echo 1)" \
  "WatchdogSec=$wd; new PID ${newpid:-none} ${took}s after SIGSTOP (limit ${wd_s:-?}+15 s); ${wdlog:-no watchdog line}"
s=$(wait_active 180); ok=$?
check "watchdog: active again" "$([ $ok = 0 ] && [ "$(prop "$s" NRestarts)" -gt "${nr:-0}" ] && echo 0 || echo 1)" "$s"
first_frame_wait 150 > /dev/null

s=$(show); pid=$(prop "$s" MainPID); nr=$(prop "$s" NRestarts)
agent 20 "kill -KILL $pid" > /dev/null
s=$(wait_active 180); ok=$?
ff=$(first_frame_wait 150)
e=$(screendump); sleep 4; f=$(screendump)
check "SIGKILL -> restarted" "$([ $ok = 0 ] && [ "$(prop "$s" MainPID)" != "$pid" ] && [ "$(prop "$s" NRestarts)" -gt "${nr:-0}" ] && echo 0 || echo 1)" "$s"
# Back on the screen: the session the SIGKILL interrupted, restored (a still piece), or attract mode
# (moving) when the restart took longer than the session's idle time.
check "SIGKILL -> back on the screen" "$([ -n "$ff" ] && [ "$(lit "$f")" -gt 1000 ] && echo 0 || echo 1)" \
  "${ff:-no first frame}; $(lit "$f") non-black bytes; screendumps 4 s apart $(cmp -s "$e" "$f" && echo 'equal (the restored session)' || echo 'differ (attract mode)')"

boot1=$(agent 60 "timeout 40 systemctl is-system-running --wait > /dev/null; systemctl is-system-running; systemctl --failed --plain --no-legend | cut -d' ' -f1 | tr '\n' ' '")
check "first boot: no failed units" "$([ "$(echo "$boot1" | head -1)" = running ] && echo 0 || echo 1)" "$(echo "$boot1" | tr '\n' ' ')"
an=$(agent 30 "systemd-analyze 2>&1 | head -1")
kff=$(echo "$ff" | sed -n 's/^\[ *\([0-9.]*\)\].*/\1/p')

# 6. A hard power-off in the middle of a session: a visitor drawing, the sessions' partition being
# written (a writer fsyncing small files, as the session store does), then QEMU quits (no shutdown).
# The kiosk may still hold the session the SIGKILL interrupted (restored, not yet timed out) or be
# back in attract mode: either way the pen makes strokes, and the journal reports them durable.
ndur() { agent 20 "$KJ | grep -c 'journal: stroke [0-9]* durable'"; }
n0=$(ndur)
agent 20 "systemd-run --quiet --unit=emboss-test-pen2 /usr/local/lib/emboss-test/uinput_play /usr/local/lib/emboss-test/pen.events --before 3 --frame 0.005 --loop;
  echo 'written before the power cut' > /var/lib/emboss-kiosk/.boot-test-marker; sync
  systemd-run --quiet --unit=emboss-test-writer sh -c 'i=0; while :; do i=\$((i+1)); dd if=/dev/urandom of=/var/lib/emboss-kiosk/.boot-test-w\$((i % 50)) bs=4k count=16 conv=fsync status=none; done'" > /dev/null
vis=$(agent 60 "e=\$((SECONDS + 50)); while [ \$SECONDS -lt \$e ]; do [ \$($KJ | grep -c 'journal: stroke [0-9]* durable') -gt ${n0:-0} ] &&
    { $KJ | grep -m1 'state: visitor-arrived\|session: restored'; $KJ | grep 'journal: stroke [0-9]* durable' | tail -1; exit 0; }; sleep 0.5; done; exit 1")
check "power cut: a visitor's session under way" $? "$(echo "${vis:-no new 'journal: stroke N durable' line}" | tr '\n' ' ')(${n0:-0} before the pen); a writer fsyncing on the sessions partition"
# The strokes the kiosk has reported durable: at least one before the cut, the highest one just before it.
durable() { agent 20 "$KJ | sed -n 's/.*journal: stroke \([0-9]*\) durable.*/\1/p' | sort -n | tail -1"; }
for _ in $(seq 40); do d=$(durable); [ -n "$d" ] && break; sleep 2; done
sleep $((RANDOM % 4))
d=$(durable)
agent 30 "journalctl -b -o short-monotonic --no-pager" > "$job/journal-$boot_n.log"
echo quit >&7
wait "$qpid" 2>/dev/null; qpid=""
exec 6>&- 7>&-
say "power cut; booting again"

boot
if ! wait_agent 300; then
  check "power cut: boots again" 1 "no answer within 300 s"
else
  s=$(wait_active 240); ok=$?
  check "power cut: kiosk active again" $ok "$s"
  # The session under way comes back (or, if the boot took longer than the idle timeout, is closed
  # and kept): either way with every stroke reported durable before the cut.
  back=$(agent 30 "journalctl -b -u emboss-kiosk -o cat | grep -m1 'session: restored\|left unfinished'")
  n=$(echo "$back" | sed -n 's/.*restored [^:]*: \([0-9]*\) strokes.*/\1/p; s/.*closed and kept (\([0-9]*\) strokes.*/\1/p')
  check "power cut: durable strokes back" "$([ -n "$d" ] && [ -n "$n" ] && [ "$n" -ge "$d" ] && echo 0 || echo 1)" \
    "${d:-no} strokes durable before the cut; ${back:-no 'session: restored' line}"
  fsck=$(agent 30 "journalctl -b -o cat -u systemd-fsck-root -u 'systemd-fsck@*' | grep -v '^Finished\|^Starting\|^Started\|^Stopped\|Deactivated' | tr '\n' ' '; echo
    for u in systemd-fsck-root \$(systemctl list-units --all --plain --no-legend 'systemd-fsck@*' | cut -d' ' -f1); do
      echo \"\$u \$(systemctl show -p Result,ExecMainStatus \$u | tr '\n' ' ')\"; done")
  units=$(echo "$fsck" | tail -n +2)
  clean=$(echo "$fsck" | head -1 | grep -o 'clean' | wc -l)
  check "power cut: fsck clean" "$([ "$clean" -ge 2 ] && [ "$(echo "$units" | grep -c .)" -ge 2 ] && ! echo "$units" | grep -v 'Result=success' | grep -q . && ! echo "$units" | grep -v 'ExecMainStatus=0 \|ExecMainStatus=0$' | grep -q . && echo 0 || echo 1)" \
    "$(echo "$fsck" | tr '\n' ' ')"
  sleep 5
  fl=$(agent 60 "systemctl is-system-running --wait >/dev/null 2>&1; systemctl is-system-running; systemctl --failed --plain --no-legend | cut -d' ' -f1 | tr '\n' ' '")
  check "power cut: no failed units" "$([ "$(echo "$fl" | head -1)" = running ] && echo 0 || echo 1)" "$(echo "$fl" | tr '\n' ' ')"
  dp=$(agent 30 "findmnt -no SOURCE,OPTIONS /var/lib/emboss-kiosk | cut -d, -f1; cat /var/lib/emboss-kiosk/.boot-test-marker && n=\$(find /var/lib/emboss-kiosk -type f | wc -l) && find /var/lib/emboss-kiosk -type f -exec cat {} + > /dev/null && echo \"\$n files read\"")
  check "power cut: sessions partition readable" "$(echo "$dp" | grep -q ' rw' && echo "$dp" | grep -q 'before the power cut' && echo "$dp" | grep -q 'files read' && echo 0 || echo 1)" "$(echo "$dp" | tr '\n' ' ')"
  ro=$(agent 20 "findmnt -no OPTIONS / | cut -d, -f1; touch /etc/x 2>&1 | sed 's/.*: //'")
  check "root file system read-only" "$(echo "$ro" | head -1 | grep -qx ro && echo "$ro" | grep -qi 'read-only' && echo 0 || echo 1)" "$(echo "$ro" | tr '\n' ' ')"
  agent 30 "journalctl -b -o short-monotonic --no-pager" > "$job/journal-$boot_n.log"
  agent 20 "systemctl poweroff" > /dev/null
  timeout 120 tail --pid="$qpid" -f /dev/null
fi

[ $fails -gt 0 ] && keep_failure

echo
[ $fails -gt 0 ] && { echo "FAILED ($fails; the logs are kept in $kept):"; printf '%s\n' "${results[@]}" | grep '^FAIL'; }
echo "emboss appliance boot test: $(basename "$image") ($(du -h --apparent-size "$image" | cut -f1) image, $(du -h "$image" | cut -f1) used), $((SECONDS - t_all)) s"
echo "boot to first frame: ${ff_boot1:-?} s from the kernel's start to the kiosk's 'first frame on the screen' (first boot; ${kff:-?} s after the SIGKILL restart); $an"
printf '%s\n' "${results[@]}"
echo "$((${#results[@]} - fails)) passed, $fails failed"
[ "${EMBOSS_BOOT_TEST_VERBOSE:-0}" = 1 ] && { echo "--- console"; cat "$job"/console-*.log; }
[ $fails -eq 0 ]

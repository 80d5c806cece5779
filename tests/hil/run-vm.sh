#!/bin/bash
# run-vm.sh: boot Debian's own kernel under qemu, mount this machine's root file system read-only over
# 9p, and run a program (or a guest script) inside, chrooted into it. Output comes back over the serial
# console; a marker line carries the exit code.
#
#   tests/hil/run-vm.sh [OPTIONS] [--] PROGRAM [ARGS...]     run one program, exit with its exit code
#   tests/hil/run-vm.sh [OPTIONS] --guest-script FILE        run a guest script (see hil-tests.sh)
#
# Options:
#   --timeout SEC      kill the VM after SEC seconds (default 300; the program gets SEC-20): exit 124
#   --modules "A B"    kernel modules to load before the program runs (e.g. "uinput evdev")
#   --udevd            start systemd-udevd in the guest first (needed by libusb/libudev hotplug)
#   --log FILE         keep the whole console log there as well
#   --prepare          only fetch and build what the VM needs (kernel, initramfs, udevd), then exit 0
#   --quiet            do not echo the console while the VM runs (the program's output is still printed)
# Exit codes: the program's; 77 when this machine cannot run the VM (no qemu and no way to install it,
# no kernel package); 124 on timeout; 125 when the VM ended without reporting an exit code.
# Cache: ${EMBOSS_HIL_CACHE:-${XDG_CACHE_HOME:-~/.cache}/emboss-hil} (kernel, udev, initramfs). EMBOSS_HIL_REFRESH=1
# asks apt again which kernel linux-image-amd64 points at. EMBOSS_HIL_ACCEL=tcg forces software emulation
# (the default; EMBOSS_HIL_ACCEL=kvm tries KVM).
set -u -o pipefail

HIL_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=tests/hil/vm-lib.sh
. "$HIL_DIR/vm-lib.sh"

timeout_s=300
modules=""
udevd=0
log=""
guest_script=""
prepare_only=0
quiet=0
while [ $# -gt 0 ]; do
  case "$1" in
    --timeout) timeout_s=$2; shift 2 ;;
    --modules) modules=$2; shift 2 ;;
    --udevd) udevd=1; shift ;;
    --log) log=$2; shift 2 ;;
    --guest-script) guest_script=$2; shift 2 ;;
    --prepare) prepare_only=1; shift ;;
    --quiet) quiet=1; shift ;;
    --help|-h) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --) shift; break ;;
    -*) echo "run-vm.sh: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done

hil_prepare || exit $?
[ "$prepare_only" = 1 ] && exit 0

if [ -z "$guest_script" ]; then
  [ $# -gt 0 ] || { echo "run-vm.sh: no program given (see --help)" >&2; exit 2; }
  job_body=$(mktemp)
  {
    [ -n "$modules" ] && echo "hil_modprobe $modules"
    [ "$udevd" = 1 ] && echo "hil_udevd_start"
    # The program's own limit leaves the VM time to boot and report it (exit 137 when it is hit).
    inner=$((timeout_s > 40 ? timeout_s - 20 : timeout_s / 2))
    printf 'hil_test main %d' "$inner"
    printf ' %q' "$@"
    echo
  } > "$job_body"
  guest_script=$job_body
elif [ -n "$modules$([ "$udevd" = 1 ] && echo u)" ]; then
  job_body=$(mktemp)
  { [ -n "$modules" ] && echo "hil_modprobe $modules"; [ "$udevd" = 1 ] && echo "hil_udevd_start"; cat "$guest_script"; } > "$job_body"
  guest_script=$job_body
fi

console=$(mktemp)
hil_boot "$guest_script" "$timeout_s" "$console" "$quiet"
vm_rc=$?
[ -n "$log" ] && cp "$console" "$log"
[ -n "${job_body:-}" ] && rm -f "$job_body"

if [ $vm_rc -eq 124 ]; then
  echo "run-vm.sh: the VM did not finish within ${timeout_s}s" >&2
  [ "$quiet" = 1 ] && tail -20 "$console" >&2
  rm -f "$console"
  exit 124
fi
end=$(grep -a '^EMBOSS-HIL-END main ' "$console" | tail -1)
if [ "$quiet" = 1 ]; then
  # Not echoed while running: print the program's own output now.
  awk '$0 == "EMBOSS-HIL-BEGIN main" {on = 1; next} index($0, "EMBOSS-HIL-END main ") == 1 {on = 0} on {print}' "$console"
  grep -a '^EMBOSS-HIL-FATAL' "$console" >&2
fi
rm -f "$console"
if [ -n "$end" ]; then
  rc=${end#*rc=}; rc=${rc%% *}
  exit "$rc"
fi
# A guest script reports its own tests (see hil-tests.sh); it succeeded when the guest reached its end.
[ "$vm_rc" -eq 0 ] && exit 0
echo "run-vm.sh: the VM ended without reporting an exit code (status $vm_rc)" >&2
exit 125

#!/bin/bash
# boot-arm64.sh: boots the Raspberry Pi image (build-image.sh --arch arm64) as far as a machine without
# a Pi allows: its own kernel, initrd and root file system under qemu-system-aarch64 -M virt
# (Cortex-A72, the Pi 4's core, software emulated) with a virtio GPU for the screen. What this shows:
# the arm64 root file system boots with systemd as PID 1 from its read-only root, mounts the sessions
# partition, and the kiosk's unit starts, takes the screen through KMS and shows its first frame.
# What it cannot show: the Pi's own boot firmware (start4.elf, config.txt, the device tree), its
# VC4/V3D display, its GPIO header. Those need a Pi.
#
#   platform/image/boot-arm64.sh IMAGE [SECONDS]
#     IMAGE     an emboss-arm64.img made by build-image.sh --arch arm64 (booted on a copy)
#     SECONDS   how long to wait for the kiosk's first frame (default 1500: emulation is slow)
# The guest's journal is forwarded to the serial console; each line the check looks for is printed.
# Exit codes: 0 the kiosk showed its first frame, 1 it did not, 2 bad usage, 77 no qemu-system-aarch64.
set -u -o pipefail
[ $# -ge 1 ] || { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
image=$(readlink -f "$1")
limit=${2:-1500}
say() { echo "boot-arm64: $*" >&2; }
[ -f "$image" ] || { say "no image at $1"; exit 2; }
command -v qemu-system-aarch64 >/dev/null || { say "no qemu-system-aarch64 (apt-get install qemu-system-arm) -- skipped"; exit 77; }
command -v mcopy >/dev/null || { say "no mtools -- skipped"; exit 77; }

job=$(mktemp -d)
qpid=""
trap '[ -n "$qpid" ] && kill "$qpid" 2>/dev/null; rm -rf "$job"' EXIT
cp --sparse=always "$image" "$job/disk.img" || exit 1
# The Pi's FAT partition (the first, MBR) holds the kernel, the initrd and cmdline.txt.
esp=$(sfdisk -d "$job/disk.img" | awk -F'start= *' '/^\// {split($2, a, ","); print a[1]; exit}')
export MTOOLS_SKIP_CHECK=1
for f in vmlinuz initrd.img cmdline.txt; do
  mcopy -n -i "$job/disk.img@@$((esp * 512))" "::/$f" "$job/$f" || { say "no $f on the image's boot partition"; exit 1; }
done
# The image's own command line, with the Pi's console swapped for the virt machine's serial port and
# the journal forwarded to it (read-only root, fsck and the rest as shipped).
cmdline="$(sed 's/console=[^ ]*//g' "$job/cmdline.txt" | tr -s ' ') console=ttyAMA0 systemd.journald.forward_to_console=1"
say "booting $(basename "$image") under qemu-system-aarch64 -M virt (TCG; minutes)"
say "kernel command line: $cmdline"
t0=$SECONDS
timeout -k 5 "$limit" qemu-system-aarch64 -M virt -cpu cortex-a72 -smp 2 -m 1536 -nodefaults -no-user-config \
  -display none -no-reboot -accel tcg,thread=multi \
  -kernel "$job/vmlinuz" -initrd "$job/initrd.img" -append "$cmdline" \
  -drive "file=$job/disk.img,format=raw,if=virtio" -device virtio-gpu-pci \
  -serial "file:$job/console.log" -monitor none -nic none < /dev/null > "$job/qemu.log" 2>&1 &
qpid=$!
seen() { grep -a -m1 "$1" "$job/console.log" 2>/dev/null; }
while kill -0 "$qpid" 2>/dev/null && [ -z "$(seen 'first frame on the screen')" ]; do sleep 5; done
took=$((SECONDS - t0))
ok=0
for what in 'systemd\[1\]: .*Reached target local-fs.target' 'systemd\[1\]: Mounted var-lib-emboss' 'emboss-kiosk.*display: ' 'emboss-kiosk.*attract: ' 'first frame on the screen'; do
  line=$(seen "$what")
  if [ -n "$line" ]; then echo "PASS  $line"; else echo "FAIL  no line matching '$what'"; ok=1; fi
done
root=$(grep -a -m1 'EXT4-fs (vda2): mounted' "$job/console.log")
echo "root: ${root:-no 'EXT4-fs (vda2): mounted' line}"
echo "boot-arm64: $took s from QEMU's start$([ $ok = 0 ] && echo ' to the kiosk'"'"'s first frame')"
# The serial console is kept for a look afterwards.
keep="${EMBOSS_IMAGE_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/emboss-image}/boot-arm64-console.log"
mkdir -p "$(dirname "$keep")" && cp "$job/console.log" "$keep" && echo "boot-arm64: the console is in $keep"
[ $ok = 0 ] || { tail -30 "$job/console.log" >&2; cat "$job/qemu.log" >&2; }
exit $ok

#!/bin/sh
# HIL: the kiosk's DRM/KMS back end on the VM's bochs display (QEMU's bochs-display device, the
# kernel's bochs DRM driver; Debian's kernel has no vkms): a connector and its preferred mode, a GBM
# scanout surface, EGL on GBM (Mesa renders in software: kms_swrast, as on a board without a 3D
# driver), the first frame by drmModeSetCrtc and the next ones by page flips waited for.
#   kms.sh EMBOSS_KIOSK          (needs the module bochs; run by hil-tests.sh)
# Checks: the kiosk takes the kms back end on its own (--display=auto), shows frames and exits 0
# with a snapshot of the mode's size, and it is what `auto` picks before anything else.
set -u
kiosk=$1
. "$(dirname "$0")/checks.sh"

card=$(ls /dev/dri/card* 2>/dev/null | head -1)
if [ -z "$card" ]; then
  bad "no /dev/dri/card* after loading bochs"
  echo "kms.sh: $fail failed"; exit 1
fi
driver=$(basename "$(readlink -f "/sys/class/drm/$(basename "$card")/device/driver" 2>/dev/null)" 2>/dev/null)
ok "the bochs display is $card (driver ${driver:-?})"

# Attract mode on the virtual screen for a while (the VM's emulated CPU makes the first frame slow).
HOME=$tmp "$kiosk" --display=auto --attract --run-for=45 --snapshot="$tmp/kms.png" --stats \
  --sessions-dir="$tmp/sessions" > "$tmp/out" 2> "$tmp/err"
rc=$?
[ $rc -eq 0 ] && ok "the kiosk ran 45 s and exited 0" || bad "the kiosk exited $rc"
line=$(grep 'display: ' "$tmp/err" | head -1)
case "$line" in
  *"display: kms ("*) ok "auto took the kms back end: ${line#*display: }" ;;
  *) bad "auto did not take kms: ${line:-no display line}" ;;
esac
grep -q 'first frame on the screen' "$tmp/err" && ok "$(grep -o 'first frame on the screen.*' "$tmp/err")" || bad "no frame was shown"
grep -q "lost its output" "$tmp/err" && bad "the output was lost: $(grep 'lost its output' "$tmp/err")"
frames=$(sed -n 's/^stats: attract: \([0-9]*\) frames.*/\1/p' "$tmp/out" | head -1)
if [ "${frames:-0}" -ge 2 ]; then ok "$frames frames presented (the first by SetCrtc, the rest by page flips)"
else bad "only ${frames:-0} frames presented"; fi
mode=$(echo "$line" | sed -n 's/.* \([0-9]*x[0-9]*\)@.*/\1/p')
if [ -s "$tmp/kms.png" ]; then
  size=$(od -An -tu1 -j16 -N8 "$tmp/kms.png" | awk '{printf "%dx%d", $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}')
  [ -n "$mode" ] && [ "$size" = "$mode" ] && ok "the snapshot is the mode's size ($size)" || bad "snapshot $size, mode ${mode:-unknown}"
else
  bad "no snapshot"
fi
echo "--- the kiosk's log"; cat "$tmp/err"; cat "$tmp/out"
rm -rf "$tmp"
echo "kms.sh: $fail failed"
[ $fail -eq 0 ]

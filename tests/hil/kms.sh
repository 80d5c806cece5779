#!/bin/sh
# HIL: the kiosk's DRM/KMS back end on the VM's bochs display (QEMU's bochs-display device, the
# kernel's bochs DRM driver; Debian's kernel has no vkms): a connector and its preferred mode, a GBM
# scanout surface, EGL on GBM (Mesa renders in software: kms_swrast, as on a board without a 3D
# driver), the first frame by drmModeSetCrtc and the next ones by page flips waited for; then the
# display removed (the driver unbound) and back.
#   kms.sh EMBOSS_KIOSK          (needs the module bochs; run by hil-tests.sh)
# Checks: --display=auto takes kms; frames are shown; the kiosk notices the display gone, keeps
# running, takes the display again (as kms, not a fallback) once it is back; SIGTERM ends it with
# status 0 and a snapshot of the mode's size.
set -u
kiosk=$1
. "$(dirname "$0")/checks.sh"

card=$(ls /dev/dri/card* 2>/dev/null | head -1)
if [ -z "$card" ]; then
  bad "no /dev/dri/card* after loading bochs"
  echo "kms.sh: $fail failed"; exit 1
fi
pci=$(basename "$(readlink -f "/sys/class/drm/$(basename "$card")/device")")
driver=$(basename "$(readlink -f "/sys/class/drm/$(basename "$card")/device/driver")")
ok "the bochs display is $card (PCI $pci, driver $driver)"

# Attract mode on the display (the VM's emulated CPU makes the first frame slow: about 25 s).
HOME=$tmp "$kiosk" --display=auto --attract --stats --snapshot="$tmp/kms.png" --sessions-dir="$tmp/sessions" \
  > "$tmp/out" 2> "$tmp/err" &
pid=$!
if wait_for 120 grep -q 'first frame on the screen' "$tmp/err"; then ok "$(grep -o 'first frame on the screen.*' "$tmp/err")"
else bad "no frame was shown within 120 s"; fi
line=$(grep 'display: ' "$tmp/err" | head -1)
case "$line" in
  *"display: kms ("*) ok "auto took the kms back end: ${line#*display: }" ;;
  *) bad "auto did not take kms: ${line:-no display line}" ;;
esac
sleep 5

# The display goes away (the driver unbound: the card node disappears) and comes back.
echo "$pci" > "/sys/bus/pci/drivers/$driver/unbind"
if wait_for 30 grep -q 'lost its output' "$tmp/err"; then ok "the kiosk noticed the display gone: $(grep -m1 'lost its output' "$tmp/err")"
else bad "the kiosk did not notice the display's removal within 30 s"; fi
sleep 3
kill -0 $pid 2>/dev/null && ok "the kiosk runs on without a display" || bad "the kiosk ended when the display went away"
echo "$pci" > "/sys/bus/pci/drivers/$driver/bind"
if wait_for 60 grep -q 'display: back: kms' "$tmp/err"; then ok "the display is back: $(grep -m1 'display: back' "$tmp/err")"
else bad "the kiosk did not take the display again within 60 s: $(grep 'display: back' "$tmp/err")"; fi
sleep 5

kill -TERM $pid 2>/dev/null
if wait_for 60 sh -c "! kill -0 $pid 2>/dev/null"; then
  wait $pid; rc=$?
  [ $rc -eq 0 ] && ok "SIGTERM ends the kiosk with status 0" || bad "the kiosk exited $rc on SIGTERM"
else
  bad "the kiosk did not end within 60 s of SIGTERM"; kill -KILL $pid
fi
frames=$(sed -n 's/^stats: attract: \([0-9]*\) frames.*/\1/p' "$tmp/out" | head -1)
if [ "${frames:-0}" -ge 2 ]; then ok "$frames frames presented (by SetCrtc, then page flips)"
else bad "only ${frames:-0} frames presented"; fi
mode=$(echo "$line" | sed -n 's/.* \([0-9]*x[0-9]*\)@.*/\1/p')
if [ -s "$tmp/kms.png" ]; then
  size=$(od -An -tu1 -j16 -N8 "$tmp/kms.png" | awk '{printf "%dx%d", $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}')
  [ -n "$mode" ] && [ "$size" = "$mode" ] && ok "the snapshot is the mode's size ($size)" || bad "snapshot $size, mode ${mode:-unknown}"
else
  bad "no snapshot"
fi
echo "--- the kiosk's log"; grep -v '^MESA-LOADER\|^pci id\|^failed to load driver\|^kmsro' "$tmp/err"; cat "$tmp/out"
rm -rf "$tmp"
echo "kms.sh: $fail failed"
[ $fail -eq 0 ]

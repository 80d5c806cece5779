#!/bin/sh
# HIL: the kiosk's DRM/KMS back end on the VM's bochs display (QEMU's bochs-display device, the
# kernel's bochs DRM driver; Debian's kernel has no vkms): a connector and its preferred mode, the
# first frame by drmModeSetCrtc and the next ones by page flips waited for; then the display removed
# (the driver unbound) and back. The GL here is software (llvmpipe, as on a board without a 3D
# driver), so the kiosk draws off screen and copies each frame into the card's dumb buffers
# (kms_scanout.h); a second, shorter run forces the GBM path (EGL on a GBM surface), the one a
# board with a GPU takes.
#   kms.sh EMBOSS_KIOSK          (needs the module bochs; run by hil-tests.sh)
# Checks: --display=auto takes kms with dumb buffers; frames are shown; the kiosk notices the display
# gone, keeps running, takes the display again (as kms, not a fallback) once it is back, also when
# the card is removed at random moments of its drawing (the first removal in the middle of the slow
# first frame); SIGTERM ends it with status 0 and a snapshot of the mode's size; the GBM path shows
# frames and ends on SIGTERM with status 0.
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
# First a removal in the middle of the first frame (tracing and drawing it takes seconds here): the
# moment the GBM path used to die in Mesa's drawing thread.
lost() { grep -c 'lost its output' "$tmp/err"; }
back() { grep -c 'display: back: kms' "$tmp/err"; }
HOME=$tmp "$kiosk" --display=auto --attract --stats --sessions-dir="$tmp/sessions" > "$tmp/out0" 2> "$tmp/err" &
pid=$!
if wait_for 60 grep -q 'display: kms' "$tmp/err"; then
  sleep 2
  if grep -q 'first frame on the screen' "$tmp/err"; then
    ok "(the first frame came before the removal; the removal is mid-attract instead)"
  fi
  echo "$pci" > "/sys/bus/pci/drivers/$driver/unbind"
  if wait_for 60 sh -c "[ \$(grep -c 'lost its output' '$tmp/err') -ge 1 ] || ! kill -0 $pid 2>/dev/null"; then :; fi
  sleep 1
  kill -0 $pid 2>/dev/null && ok "removed during the first frame: the kiosk runs on ($(grep -m1 'lost its output' "$tmp/err" || echo 'no loss noticed yet'))" ||
    { wait $pid; bad "removed during the first frame: the kiosk ended (status $?)"; }
  echo "$pci" > "/sys/bus/pci/drivers/$driver/bind"
  wait_for 60 grep -q 'display: back: kms' "$tmp/err" || bad "the display did not come back after the first-frame removal"
else
  bad "no kms display within 60 s: $(grep 'display' "$tmp/err" | head -2)"
fi
kill -TERM $pid 2>/dev/null
wait_for 60 sh -c "! kill -0 $pid 2>/dev/null" || { bad "the kiosk did not end within 60 s of SIGTERM after the first-frame removal"; stacks $pid; kill -KILL $pid; }
cat "$tmp/err" > "$tmp/err0"

HOME=$tmp "$kiosk" --display=auto --attract --stats --snapshot="$tmp/kms.png" --sessions-dir="$tmp/sessions" \
  > "$tmp/out" 2> "$tmp/err" &
pid=$!
if wait_for 120 grep -q 'first frame on the screen' "$tmp/err"; then ok "$(grep -o 'first frame on the screen.*' "$tmp/err")"
else bad "no frame was shown within 120 s"; fi
line=$(grep 'display: ' "$tmp/err" | head -1)
case "$line" in
  *"display: kms ("*"dumb buffers)"*) ok "auto took the kms back end, with dumb buffers for the software GL: ${line#*display: }" ;;
  *) bad "auto did not take kms with dumb buffers: ${line:-no display line}" ;;
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

# The card removed at random moments while attract mode draws and flips.
survived=0
for i in 1 2 3 4 5; do
  before=$(lost) backs=$(back)
  sleep "$(awk -v s="$(date +%N)" -v i=$i 'BEGIN { srand(s + i); printf "%.2f", rand() * 1.5 }')"
  echo "$pci" > "/sys/bus/pci/drivers/$driver/unbind"
  wait_for 30 sh -c "[ \$(grep -c 'lost its output' '$tmp/err') -gt $before ] || ! kill -0 $pid 2>/dev/null"
  kill -0 $pid 2>/dev/null || break
  echo "$pci" > "/sys/bus/pci/drivers/$driver/bind"
  wait_for 60 sh -c "[ \$(grep -c 'display: back: kms' '$tmp/err') -gt $backs ] || ! kill -0 $pid 2>/dev/null"
  kill -0 $pid 2>/dev/null && [ "$(back)" -gt "$backs" ] || break
  survived=$i
done
[ $survived = 5 ] && ok "5 removals at random moments of the drawing: each noticed, the display back each time" ||
  bad "removal $((survived + 1)) at a random moment: $(kill -0 $pid 2>/dev/null && echo 'the display did not come back' || echo 'the kiosk ended')"

# The snapshot's frame is traced to the end for at most 10 s (an exact 1280x800 frame takes up to a
# minute on the VM's emulated CPU, and systemd waits 15 s), then presented as far as it got.
kill -TERM $pid 2>/dev/null
term=$(date +%s)
if wait_for 60 sh -c "! kill -0 $pid 2>/dev/null"; then
  wait $pid; rc=$?
  last=$(grep -m1 'stopping: ' "$tmp/err" | sed 's/^emboss-kiosk: //')
  [ $rc -eq 0 ] && ok "SIGTERM ends the kiosk with status 0 in $(($(date +%s) - term)) s${last:+ ($last)}" || bad "the kiosk exited $rc on SIGTERM"
else
  bad "the kiosk did not end within 60 s of SIGTERM"; stacks $pid; kill -KILL $pid
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

# The GBM path (EGL on a GBM surface, Mesa drawing into the card's buffers), forced: frames and a
# clean end.
EMBOSS_KMS_SCANOUT=gbm HOME=$tmp "$kiosk" --display=kms --attract --stats --sessions-dir="$tmp/sessions" > "$tmp/out-gbm" 2> "$tmp/err-gbm" &
pid=$!
if wait_for 120 grep -q 'first frame on the screen' "$tmp/err-gbm"; then
  gl=$(grep 'display: ' "$tmp/err-gbm" | head -1)
  case "$gl" in
    *"display: kms ("*"dumb buffers"*) bad "EMBOSS_KMS_SCANOUT=gbm still took dumb buffers: $gl" ;;
    *"display: kms ("*) ok "EMBOSS_KMS_SCANOUT=gbm: the GBM path shows frames (${gl#*display: })" ;;
    *) bad "EMBOSS_KMS_SCANOUT=gbm: no kms display: ${gl:-no display line}" ;;
  esac
else
  bad "the GBM path showed no frame within 120 s: $(grep -v '^MESA\|^pci id\|^failed to load' "$tmp/err-gbm" | tail -3)"
fi
sleep 3
kill -TERM $pid 2>/dev/null
if wait_for 60 sh -c "! kill -0 $pid 2>/dev/null"; then
  wait $pid; rc=$?
  [ $rc -eq 0 ] && ok "the GBM path ends on SIGTERM with status 0" || bad "the GBM path exited $rc on SIGTERM"
else
  bad "the GBM path did not end within 60 s of SIGTERM"; stacks $pid; kill -KILL $pid
fi

echo "--- the kiosk's log (the first-frame removal)"; grep -v '^MESA-LOADER\|^pci id\|^failed to load driver\|^kmsro' "$tmp/err0"
echo "--- the kiosk's log"; grep -v '^MESA-LOADER\|^pci id\|^failed to load driver\|^kmsro' "$tmp/err"; cat "$tmp/out"
echo "--- the kiosk's log (GBM)"; grep -v '^MESA-LOADER\|^pci id\|^failed to load driver\|^kmsro' "$tmp/err-gbm"
rm -rf "$tmp"
echo "kms.sh: $fail failed"
[ $fail -eq 0 ]

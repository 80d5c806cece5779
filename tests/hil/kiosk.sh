#!/bin/sh
# HIL: the whole kiosk, headless, with a uinput tablet (a recording replayed in a loop) and the vivid
# camera as its devices. Run by hil-tests.sh when BUILD_DIR/firmware-app/emboss-kiosk exists.
#   kiosk.sh EMBOSS_KIOSK UINPUT_PLAY EVEMU_DIR          (needs the modules uinput evdev vivid)
# The checks only assume what any kiosk built on the platform back ends does: it keeps running, it
# holds the tablet's event node and the camera's video node open (seen in /proc/PID/fd), it takes
# the tablet again after an unplug, it survives the camera's removal, lets go of it and takes it
# again when it is back, and it ends on SIGTERM.
# EMBOSS_HIL_KIOSK_ARGS: the kiosk's arguments (default "--display headless --size 320x200": the VM
# emulates its CPU, so the picture is kept small).
set -u
kiosk=$1 play=$2 evemu=$3
args=${EMBOSS_HIL_KIOSK_ARGS:---display headless --size 320x200}
events="$evemu/Genius EasyPen i405X.events"
. "$(dirname "$0")/checks.sh"
holds() { ls -l "/proc/$1/fd" 2>/dev/null | grep -q " -> $2\$"; }
start_tablet() {
  "$play" "$events" --before 0 --frame 0.005 --loop > "$tmp/play.out" 2>&1 &
  tablet=$!
  wait_for 10 grep -q '^node ' "$tmp/play.out"
  node=$(sed -n 's/^node //p' "$tmp/play.out")
}
capture_node() {  # vivid's video capture node (its number can change when vivid is bound again)
  for v in /sys/class/video4linux/video*; do
    grep -q 'vid-cap' "$v/name" 2>/dev/null && echo "/dev/$(basename "$v")"
  done | head -1
}
video=$(capture_node)
vivid=$(ls /sys/bus/platform/drivers/vivid 2>/dev/null | grep '^vivid\.' | head -1)

start_tablet
[ -n "$node" ] && ok "uinput tablet at $node, vivid capture at ${video:-none}" || bad "no uinput tablet"

# shellcheck disable=SC2086
# The kiosk's log, each line with the test's time.
mkfifo "$tmp/fifo"
(while IFS= read -r l; do echo "[$(at)] $l"; done < "$tmp/fifo" > "$tmp/kiosk.err") &
"$kiosk" $args > "$tmp/kiosk.out" 2> "$tmp/fifo" &
pid=$!
if wait_for 30 holds $pid "$node"; then ok "the kiosk opened the tablet $node"; else bad "the kiosk did not open $node within 30 s"; fi
if [ -n "$video" ]; then
  if wait_for 30 holds $pid "$video"; then ok "the kiosk opened the camera $video"; else bad "the kiosk did not open $video within 30 s"; fi
fi
# The first frame: the piece under way is built first, which under the VM's emulated CPU takes
# half a minute (half a second on the development machine).
if wait_for 120 grep -q 'first frame on the screen' "$tmp/kiosk.err"; then ok "the kiosk shows its first frame"
else bad "the kiosk showed no frame within 120 s"; fi
sleep 3
kill -0 $pid 2>/dev/null && ok "the kiosk runs with a pen drawing on it" || bad "the kiosk ended early"

# Tablet unplugged and plugged in again.
kill $tablet; wait $tablet 2>/dev/null
sleep 1
start_tablet
if wait_for 15 holds $pid "$node"; then ok "after an unplug the kiosk took the tablet again ($node)"; else bad "the kiosk did not take the replugged tablet $node within 15 s"; fi

# Camera removed and back.
if [ -n "$vivid" ]; then
  echo "$vivid" > /sys/bus/platform/drivers/vivid/unbind
  sleep 3
  kill -0 $pid 2>/dev/null && ok "the kiosk survives the camera's removal" || bad "the kiosk died when the camera went away"
  if wait_for 10 sh -c "! ls -l /proc/$pid/fd 2>/dev/null | grep -q ' -> $video\$'"; then
    ok "the kiosk let go of the removed camera"
  else
    bad "the kiosk still holds $video 10 s after its removal"
  fi
  echo "$vivid" > /sys/bus/platform/drivers/vivid/bind
  sleep 1
  video=$(capture_node)
  if [ -n "$video" ] && wait_for 15 holds $pid "$video"; then ok "the kiosk took the camera again once it was back ($video)"
  else bad "the kiosk did not take the camera ${video:-(no capture node)} again within 15 s of its return"; fi
fi

kill -TERM $pid
if wait_for 30 sh -c "! kill -0 $pid 2>/dev/null"; then
  wait $pid; rc=$?
  [ $rc -eq 0 ] && ok "SIGTERM ends the kiosk with status 0" || bad "the kiosk exited $rc on SIGTERM"
else
  bad "the kiosk did not end within 30 s of SIGTERM"; stacks $pid; kill -KILL $pid
fi
kill $tablet 2>/dev/null
echo "--- the kiosk's log (last 20 lines)"; tail -20 "$tmp/kiosk.err"
rm -rf "$tmp"
echo "kiosk.sh: $fail failed"
[ $fail -eq 0 ]

#!/bin/sh
# HIL: the whole kiosk, headless, with a uinput tablet (a recording replayed in a loop) and the vivid
# camera as its devices. Run by hil-tests.sh when BUILD_DIR/firmware-app/emboss-kiosk exists.
#   kiosk.sh EMBOSS_KIOSK UINPUT_PLAY EVEMU_DIR          (needs the modules uinput evdev vivid)
# The checks only assume what any kiosk built on the platform back ends does: it keeps running, it
# holds the tablet's event node and the camera's video node open (seen in /proc/PID/fd), it takes
# the tablet again after an unplug, it survives the camera's removal, and it ends on SIGTERM.
# EMBOSS_HIL_KIOSK_ARGS: the kiosk's arguments for a headless run (default "--display headless"),
# to be fitted to emboss-kiosk's command line once it exists.
set -u
kiosk=$1 play=$2 evemu=$3
args=${EMBOSS_HIL_KIOSK_ARGS:---display headless}
events="$evemu/Genius EasyPen i405X.events"
tmp=$(mktemp -d)
fail=0
ok() { echo "ok - $*"; }
bad() { echo "FAIL - $*"; fail=$((fail + 1)); }
holds() { ls -l "/proc/$1/fd" 2>/dev/null | grep -q " -> $2\$"; }
wait_for() {  # wait_for SECONDS COMMAND...: true once COMMAND succeeds
  limit=$1; shift
  n=0
  while ! "$@"; do
    n=$((n + 1)); [ $n -gt $((limit * 10)) ] && return 1
    sleep 0.1
  done
}
start_tablet() {
  "$play" "$events" --before 0 --frame 0.005 --loop > "$tmp/play.out" 2>&1 &
  tablet=$!
  wait_for 10 grep -q '^node ' "$tmp/play.out"
  node=$(sed -n 's/^node //p' "$tmp/play.out")
}
video=$(for v in /sys/class/video4linux/video*; do
  grep -q 'vid-cap' "$v/name" 2>/dev/null && echo "/dev/$(basename "$v")"; done | head -1)
vivid=$(ls /sys/bus/platform/drivers/vivid 2>/dev/null | grep '^vivid\.' | head -1)

start_tablet
[ -n "$node" ] && ok "uinput tablet at $node, vivid capture at ${video:-none}" || bad "no uinput tablet"

# shellcheck disable=SC2086
"$kiosk" $args > "$tmp/kiosk.out" 2> "$tmp/kiosk.err" &
pid=$!
if wait_for 30 holds $pid "$node"; then ok "the kiosk opened the tablet $node"; else bad "the kiosk did not open $node within 30 s"; fi
if [ -n "$video" ]; then
  if wait_for 30 holds $pid "$video"; then ok "the kiosk opened the camera $video"; else bad "the kiosk did not open $video within 30 s"; fi
fi
sleep 3
kill -0 $pid 2>/dev/null && ok "the kiosk runs with a pen drawing on it" || bad "the kiosk ended early"

# Tablet unplugged and plugged in again.
kill $tablet; wait $tablet 2>/dev/null
sleep 1
start_tablet
if wait_for 5 holds $pid "$node"; then ok "after an unplug the kiosk took the tablet again ($node)"; else bad "the kiosk did not take the replugged tablet $node within 5 s"; fi

# Camera removed and back.
if [ -n "$vivid" ]; then
  echo "$vivid" > /sys/bus/platform/drivers/vivid/unbind
  sleep 3
  kill -0 $pid 2>/dev/null && ok "the kiosk survives the camera's removal" || bad "the kiosk died when the camera went away"
  echo "$vivid" > /sys/bus/platform/drivers/vivid/bind
  sleep 3
fi

kill -TERM $pid
if wait_for 10 sh -c "! kill -0 $pid 2>/dev/null"; then
  wait $pid; rc=$?
  [ $rc -eq 0 ] && ok "SIGTERM ends the kiosk with status 0" || bad "the kiosk exited $rc on SIGTERM"
else
  bad "the kiosk did not end within 10 s of SIGTERM"; kill -KILL $pid
fi
kill $tablet 2>/dev/null
echo "--- the kiosk's log (last 20 lines)"; tail -20 "$tmp/kiosk.err"
rm -rf "$tmp"
echo "kiosk.sh: $fail failed"
[ $fail -eq 0 ]

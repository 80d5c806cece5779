#!/bin/sh
# HIL: the emboss-input program against a live uinput tablet: `list` names it usable, `monitor` prints
# the samples of a recording replayed into it, and they are the ones `evemu FILE` decodes offline.
#   emboss_input.sh EMBOSS_INPUT UINPUT_PLAY EVENTS_FILE        (needs the modules uinput and evdev)
set -u
input=$1 play=$2 events=$3
tmp=$(mktemp -d)
fail=0
ok() { echo "ok - $*"; }
bad() { echo "FAIL - $*"; fail=$((fail + 1)); }

"$play" "$events" --before 0 --start-file "$tmp/start" --frame 0.01 --after 3 > "$tmp/play.out" 2>&1 &
pid=$!
i=0
while ! grep -q '^node ' "$tmp/play.out" && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
node=$(sed -n 's/^node //p' "$tmp/play.out")
[ -n "$node" ] && ok "uinput tablet $node" || bad "no uinput tablet: $(cat "$tmp/play.out")"

"$input" list > "$tmp/list.txt" 2>&1
if grep -A1 "^evdev  *$node " "$tmp/list.txt" | grep -q 'usable: evdev back end'; then
  ok "emboss-input list shows $node as a usable evdev tablet"
else
  bad "emboss-input list does not show $node usable:"; cat "$tmp/list.txt"
fi

# monitor until the replay is over (SIGTERM ends it with status 0); the replay starts once it monitors.
"$input" monitor --seconds 120 > "$tmp/live.txt" 2> "$tmp/monitor.err" &
mon=$!
i=0
while ! grep -q 'monitoring' "$tmp/monitor.err" && [ $i -lt 300 ]; do sleep 0.1; i=$((i + 1)); done
touch "$tmp/start"
i=0
while ! grep -q '^replayed' "$tmp/play.out" && [ $i -lt 300 ]; do sleep 0.1; i=$((i + 1)); done
sleep 0.5
kill -TERM $mon
wait $mon
rc=$?
wait $pid
[ $rc -eq 0 ] && ok "emboss-input monitor read the replay ($(wc -l < "$tmp/live.txt") samples; $(grep -m1 monitoring "$tmp/monitor.err"))" ||
  bad "emboss-input monitor exited $rc: $(cat "$tmp/monitor.err")"
"$input" evemu "$events" > "$tmp/offline.txt" 2>&1 || bad "emboss-input evemu failed: $(cat "$tmp/offline.txt")"
# time x y pressure tip in_range: compare all but time, repeats removed (the kernel drops unchanged values).
cut -d' ' -f2- "$tmp/live.txt" | uniq > "$tmp/live.cmp"
cut -d' ' -f2- "$tmp/offline.txt" | uniq > "$tmp/offline.cmp"
if [ -s "$tmp/offline.cmp" ] && cmp -s "$tmp/live.cmp" "$tmp/offline.cmp"; then
  ok "monitor's samples equal evemu's offline decoding ($(wc -l < "$tmp/offline.cmp") distinct samples)"
else
  bad "monitor's samples differ from the offline decoding ($(wc -l < "$tmp/live.cmp") live, $(wc -l < "$tmp/offline.cmp") offline):"
  diff "$tmp/offline.cmp" "$tmp/live.cmp" | head -10
fi
rm -rf "$tmp"
echo "emboss_input.sh: $fail failed"
[ $fail -eq 0 ]

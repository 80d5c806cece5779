#!/usr/bin/env bash
# emboss bench --kiosk: the kiosk program run headless on a real tablet recording played in a loop
# at its own pace; the table of what a visitor feels read back. Timing is not judged here (the
# bench prints whether the targets are met); what is checked is that every row was measured.
set -u
bin="$1"; src="$2"
emboss="$bin/emboss"
rec="$src/../shared/fixtures/evemu/Wacom Intuos4 6x9.stylus-drag.events"
[ -x "$bin/emboss-kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
[ -f "$rec" ] || { echo "skip: no tablet recordings (the fixtures are not beside the checkout: $src/../shared/fixtures)"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
mkdir "$tmp/tmpdir"
TMPDIR="$tmp/tmpdir" "$emboss" bench --quick --only kiosk --threads 2 --kiosk "$rec" --kiosk-loops 2 -o "$tmp/bench.md" >"$tmp/out" 2>"$tmp/err"; rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL bench --kiosk: exit $rc"; cat "$tmp/out" "$tmp/err"; exit 1; }
row() { grep "^| $1" "$tmp/out"; }
# One loop of the drag recording changes the picture 23 times at its pace: two loops give more.
updates=$(row "stroke-to-screen latency" | sed -nE 's/.*\| ([0-9]+) updates: mean [0-9.]+ ms, median [0-9.]+, 95 % [0-9.]+, 99 % [0-9.]+, max [0-9.]+ ms \| 99 % <= 16 ms, >= 100 updates \| (yes|\*\*no\*\*).*/\1/p')
if [ -z "$updates" ] || [ "$updates" -le 23 ]; then echo "FAIL latency row (updates '$updates'): $(row stroke)"; fail=1; else echo "ok   latency over $updates updates"; fi
row "CPU while the visitor stands idle" | grep -Eq '\| [0-9.]+ % of one core \| near zero' &&
  echo "ok   idle CPU: $(row CPU | cut -d'|' -f3)" || { echo "FAIL idle row: $(row CPU)"; fail=1; }
# The sheet the recording left, as the kiosk saved it: full frames of it against the baseline.
row "full frame of the sheet the recording left" |
  grep -Eq '^\| full frame of the sheet the recording left \([1-9][0-9]* operations, [0-9]+ set operations, [0-9]+ patina strokes\), 320x200 \| [0-9.]+ ms \(median of 2\), [0-9.]+x the baseline.s [0-9.]+ ms \| <= 1.5x the baseline \| (yes|\*\*no\*\*) \|$' &&
  echo "ok   the sheet left: $(row "full frame" | cut -d'|' -f3)" || { echo "FAIL sheet row: $(row "full frame")"; fail=1; }
# Kept beside the report: the session the kiosk saved, and the very frame that was timed (a render
# of that session at the same size gives its bytes).
ops=$(row "full frame of the sheet the recording left" | sed -nE 's/^\| full frame of the sheet the recording left \(([0-9]+) operations.*/\1/p')
again=$("$emboss" render "$tmp/bench-sheet.json" -o "$tmp/again.png" --size 320x200 --threads 1 2>&1)
if grep -q "^The sheet the recording left: kept as bench-sheet.json (the session the kiosk saved) and bench-sheet.png (the full frame timed)\.$" "$tmp/out" &&
   [ -n "$ops" ] && echo "$again" | grep -q "^render: 320x200, $ops operations," && cmp -s "$tmp/bench-sheet.png" "$tmp/again.png"; then
  echo "ok   the sheet kept: $ops operations, its picture the frame timed"
else echo "FAIL the sheet kept (row's operations '$ops'): $(grep "^The sheet the recording left" "$tmp/out"); $again; $(cmp "$tmp/bench-sheet.png" "$tmp/again.png" 2>&1)"; fail=1; fi
row "attract mode" | grep -Eq '\| [0-9.]+ fps from its first frame on \([0-9]+ frames in [0-9.]+ s\) \| >= 30 fps' &&
  echo "ok   attract: $(row attract | cut -d'|' -f3)" || { echo "FAIL attract row: $(row attract)"; fail=1; }
grep -q "played 2 times, a second apart, at its own pace" "$tmp/out" || { echo "FAIL the table does not say how the recording was played"; fail=1; }
# The bench's temporary folder (under TMPDIR) is gone.
[ -z "$(ls -A "$tmp/tmpdir")" ] || { echo "FAIL left a temporary folder behind: $(ls -A "$tmp/tmpdir")"; fail=1; }

# A recording with no events: a clear message, exit 1.
printf '# EVEMU 1.3\nN: nothing\n' >"$tmp/empty.events"
"$emboss" bench --quick --only kiosk --kiosk "$tmp/empty.events" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ "$rc" -eq 1 ] && grep -q "empty.events holds no events" "$tmp/err"; then echo "ok   empty recording"; else
  echo "FAIL empty recording: exit $rc, $(cat "$tmp/err")"; fail=1; fi

# A kiosk that cannot start: the bench says why (the kiosk's own words) at once, not after the
# recording's time. The bench runs the emboss-kiosk beside it: a copy of it beside a stand-in.
mkdir -p "$tmp/fake"
cp "$emboss" "$tmp/fake/emboss"
printf '#!/bin/sh\necho "emboss-kiosk: headless: cannot start the display (a test)" >&2\nexit 1\n' >"$tmp/fake/emboss-kiosk"
chmod +x "$tmp/fake/emboss-kiosk"
start=$SECONDS
"$tmp/fake/emboss" bench --quick --only kiosk --kiosk "$rec" >"$tmp/out" 2>"$tmp/err"; rc=$?
if [ "$rc" -eq 1 ] && grep -q "failed: emboss-kiosk: headless: cannot start the display (a test)" "$tmp/err" &&
   [ $((SECONDS - start)) -lt 8 ]; then echo "ok   a kiosk that cannot start: $((SECONDS - start)) s"; else
  echo "FAIL a kiosk that cannot start: exit $rc after $((SECONDS - start)) s, $(cat "$tmp/err")"; fail=1; fi
exit $fail

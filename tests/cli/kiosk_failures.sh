#!/usr/bin/env bash
# emboss-kiosk under bad conditions: display back ends that cannot start say why, and bad input
# (a missing recording, broken pieces, a bad config, a blocked sessions folder) is a clear log
# line and a safe fallback, never a crash.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
check() {  # check NAME EXPECTED_RC COMMAND...
  local name="$1" want="$2"; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"; local rc=$?
  if [ "$rc" -ne "$want" ]; then echo "FAIL $name: exit $rc, wanted $want"; cat "$tmp/out" "$tmp/err"; fail=1; else echo "ok   $name"; fi
}
expect_log() {  # expect_log NAME PATTERN
  grep -q -- "$2" "$tmp/err" || { echo "FAIL $1: no '$2' in the log:"; cat "$tmp/err"; fail=1; }
}
base=(--size 320x200 --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces")

check "help" 0 "$kiosk" --help
grep -q -- "--tablet" "$tmp/out" || { echo "FAIL help lacks --tablet"; fail=1; }
check "unknown option" 2 "$kiosk" --bogus
check "bad display kind" 2 "$kiosk" --display=vga
check "bad size" 2 "$kiosk" --display=headless --size 12
check "fast without a recording" 2 "$kiosk" --display=headless --fast
expect_log "fast without a recording" "give --tablet=evemu:PATH"

# Display back ends that cannot start: a clear message naming the back end, exit 1.
check "x11 without DISPLAY" 1 env -u DISPLAY "$kiosk" "${base[@]}" --display=x11 --run-for=1
expect_log "x11 without DISPLAY" "x11: "
if ! ls /dev/dri/card* >/dev/null 2>&1; then
  check "kms without a GPU" 1 "$kiosk" "${base[@]}" --display=kms --run-for=1
  expect_log "kms without a GPU" "kms: "
fi

# Headless must work for the rest (skip when this machine has no EGL at all).
"$kiosk" "${base[@]}" --display=headless --run-for=0.5 >"$tmp/out" 2>"$tmp/err"
if [ $? -ne 0 ]; then echo "skip: headless display unavailable: $(cat "$tmp/err")"; exit 77; fi

# A missing recording: logged, the kiosk runs without a pen; with --fast the exit says so.
check "missing recording" 1 "$kiosk" "${base[@]}" --display=headless --tablet=evemu:"$tmp/none.events" --fast --snapshot="$tmp/m.png"
expect_log "missing recording" "going on without a pen"
[ -s "$tmp/m.png" ] || { echo "FAIL no snapshot after a missing recording"; fail=1; }
check "missing recording, live" 0 "$kiosk" "${base[@]}" --display=headless --tablet=evemu:"$tmp/none.events" --run-for=0.5

# Broken attract pieces are skipped, good ones play; with none left the built-in ones play.
mkdir -p "$tmp/pieces"
echo '{"operations": [' >"$tmp/pieces/broken.json"
cp "$src/firmware-app/pieces/1-rosette.json" "$tmp/pieces/"
check "broken piece" 0 "$kiosk" --size 320x200 --sessions-dir "$tmp/sessions" --display=headless --attract --run-for=0.5 --pieces "$tmp/pieces"
expect_log "broken piece" "skipping a piece that does not read: broken.json"
expect_log "broken piece" "1 pieces from"
rm "$tmp/pieces/1-rosette.json"
check "only broken pieces" 0 "$kiosk" --size 320x200 --sessions-dir "$tmp/sessions" --display=headless --attract --run-for=0.5 --pieces "$tmp/pieces"
expect_log "only broken pieces" "built-in pieces"

# A config with bad lines: each is a warning, the rest applies.
printf 'display = headless\nidle_seconds = soon\nfrobnicate = 1\nsize = 320x200\n' >"$tmp/k.conf"
check "bad config lines" 0 "$kiosk" --config "$tmp/k.conf" --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces" --run-for=0.5 --snapshot="$tmp/c.png"
expect_log "bad config lines" "k.conf:2: idle_seconds must be a positive number"
expect_log "bad config lines" "k.conf:3: unknown key 'frobnicate'"
grep -q "(320x200)" "$tmp/out" || { echo "FAIL config size not applied: $(cat "$tmp/out")"; fail=1; }
check "missing config" 0 "$kiosk" --config "$tmp/none.conf" "${base[@]}" --display=headless --run-for=0.3
expect_log "missing config" "using the defaults"

# Sessions cannot be written (a file where the folder should be): logged, kept, the run goes on
# and --session-out still gets the visitor's work.
echo "not a folder" >"$tmp/blocked"
check "blocked sessions" 0 "$kiosk" --size 320x200 --pieces "$src/firmware-app/pieces" --display=headless --sessions-dir "$tmp/blocked/s" \
  --tablet=evemu:"$src/tests/app/data/visitor-demo.events" --fast --session-out="$tmp/s.json"
expect_log "blocked sessions" "keeping the session"
[ "$(grep -c '"op":' "$tmp/s.json")" -ge 100 ] || { echo "FAIL --session-out lost the work"; fail=1; }

# An unwritable snapshot path: a message and exit 1, not a crash.
check "unwritable snapshot" 1 "$kiosk" "${base[@]}" --display=headless --run-for=0.3 --snapshot="$tmp/blocked/x.png"
expect_log "unwritable snapshot" "snapshot: "
exit $fail

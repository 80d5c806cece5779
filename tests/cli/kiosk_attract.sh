#!/usr/bin/env bash
# The README's command: a window on a desktop, else headless attract mode for a few seconds that
# writes a snapshot and says where; --stats gives the attract frame rate; --staff shows staff mode.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
cd "$tmp" || exit 1
# Run from the checkout's root as the README does, but without a desktop (DISPLAY unset).
env -u DISPLAY "$kiosk" --display=auto --attract --run-for=2 --snapshot=out/kiosk.png --size 480x300 --stats \
  --pieces "$src/firmware-app/pieces" --sessions-dir "$tmp/s" >"$tmp/o" 2>"$tmp/e"
rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL attract: exit $rc"; cat "$tmp/o" "$tmp/e"; fail=1; }
grep -q "wrote snapshot $tmp/out/kiosk.png" "$tmp/o" || { echo "FAIL does not say where the snapshot is:"; cat "$tmp/o"; fail=1; }
[ -s out/kiosk.png ] || { echo "FAIL no out/kiosk.png"; fail=1; }
grep -Eq "stats: attract: [0-9]+ frames in [0-9.]+ s = [0-9.]+ fps; [0-9.]+ fps from its first frame on" "$tmp/o" || { echo "FAIL no attract fps"; cat "$tmp/o"; fail=1; }
grep -q "display: " "$tmp/e" || { echo "FAIL the display chosen is not logged"; fail=1; }
[ "$fail" -eq 0 ] && echo "ok   attract ($(grep 'stats: attract' "$tmp/o"))"
"$kiosk" --display=headless --staff --run-for=0.5 --snapshot="$tmp/staff.png" --size 480x300 --pieces "$src/firmware-app/pieces" \
  --sessions-dir "$tmp/s" >"$tmp/o" 2>"$tmp/e" || { echo "FAIL staff: $(cat "$tmp/e")"; fail=1; }
grep -q "state: staff-entered" "$tmp/e" || { echo "FAIL --staff did not enter staff mode"; cat "$tmp/e"; fail=1; }
[ -s "$tmp/staff.png" ] && echo "ok   staff" || { echo "FAIL no staff snapshot"; fail=1; }
exit $fail

#!/usr/bin/env bash
# emboss-kiosk driven by a recording, headless: the session holds the strokes, the snapshot shows
# them (pixels differ from a bare sheet where the flower is), --stats prints the latency.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
demo="$src/tests/app/data/visitor-demo.events"
common=(--display=headless --size 480x300 --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces")

"$kiosk" "${common[@]}" --tablet="evemu:$demo" --fast --snapshot="$tmp/demo.png" --session-out="$tmp/demo.json" --stats \
  >"$tmp/out" 2>"$tmp/err"
rc=$?
if grep -q "headless:" "$tmp/err" && [ "$rc" -ne 0 ]; then echo "skip: no headless display here: $(cat "$tmp/err")"; exit 77; fi
[ "$rc" -eq 0 ] || { echo "FAIL replay: exit $rc"; cat "$tmp/out" "$tmp/err"; fail=1; }
grep -q "wrote snapshot" "$tmp/out" || { echo "FAIL snapshot not reported"; fail=1; }
grep -q "stats: stroke-to-screen latency: [0-9]* updates" "$tmp/out" || { echo "FAIL latency not printed"; cat "$tmp/out"; fail=1; }
[ -s "$tmp/demo.png" ] || { echo "FAIL no snapshot"; fail=1; }
ops=$(grep -c '"op":' "$tmp/demo.json")
[ "$ops" -ge 100 ] || { echo "FAIL session has $ops operations"; fail=1; }
regions=$(grep -c '"op": "region"' "$tmp/demo.json")
[ "$regions" -eq 8 ] || { echo "FAIL session has $regions regions, wanted 8 (raised petals and leaves)"; fail=1; }
# The kiosk stopping saved the session too, atomically (no .part left).
ls "$tmp/sessions"/session-*.json >/dev/null 2>&1 || { echo "FAIL no saved session"; fail=1; }
ls "$tmp/sessions"/*.part >/dev/null 2>&1 && { echo "FAIL temporary files left"; fail=1; }
echo "ok   replay ($ops operations)"

# A bare sheet to compare with: a tap beside the metal wakes the kiosk and embosses nothing.
{
  grep -v '^E:' "$demo" | grep -v '^#'
  echo "E: 1.000000 0001 0140 1"; echo "E: 1.000000 0003 0000 0"; echo "E: 1.000000 0003 0001 0"; echo "E: 1.000000 0000 0000 0"
  echo "E: 1.010000 0003 0018 900"; echo "E: 1.010000 0001 014a 1"; echo "E: 1.010000 0000 0000 0"
  echo "E: 1.020000 0003 0018 0"; echo "E: 1.020000 0001 014a 0"; echo "E: 1.020000 0000 0000 0"
  echo "E: 1.030000 0001 0140 0"; echo "E: 1.030000 0000 0000 0"
} >"$tmp/tap.events"
"$kiosk" "${common[@]}" --tablet="evemu:$tmp/tap.events" --fast --snapshot="$tmp/blank.png" --session-out="$tmp/blank.json" \
  >"$tmp/out2" 2>"$tmp/err2" || { echo "FAIL blank run"; cat "$tmp/err2"; fail=1; }
[ "$(grep -c '"op":' "$tmp/blank.json")" -eq 0 ] || { echo "FAIL a tap beside the metal embossed something"; fail=1; }
if command -v python3 >/dev/null; then
  python3 - "$tmp/demo.png" "$tmp/blank.png" <<'PY' || fail=1
import struct, sys, zlib
def read(path):
    d = open(path, 'rb').read(); pos = 8; idat = b''
    while pos < len(d):
        n, t = struct.unpack('>I4s', d[pos:pos + 8]); body = d[pos + 8:pos + 8 + n]; pos += 12 + n
        if t == b'IHDR': w, h, bd, ct = struct.unpack('>IIBB', body[:10]); ch = {2: 3, 6: 4}[ct]
        elif t == b'IDAT': idat += body
    raw = zlib.decompress(idat); st = w * ch; rows = []; prev = bytearray(st); i = 0
    for _ in range(h):
        f = raw[i]; line = bytearray(raw[i + 1:i + 1 + st]); i += 1 + st
        for x in range(st):
            a = line[x - ch] if x >= ch else 0; b = prev[x]; c = prev[x - ch] if x >= ch else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, ch, rows
w, h, ch, a = read(sys.argv[1]); _, _, ch2, b = read(sys.argv[2])
def diff(x0, y0, x1, y1):
    n = 0
    for y in range(y0, y1):
        for x in range(x0, x1):
            if sum(abs(a[y][x * ch + k] - b[y][x * ch2 + k]) for k in range(3)) > 24: n += 1
    return n / ((x1 - x0) * (y1 - y0))
# The flower sits left of the sheet's centre; the sheet's right end is untouched.
flower = diff(int(w * 0.36), int(h * 0.25), int(w * 0.56), int(h * 0.65))
right = diff(int(w * 0.74), int(h * 0.35), int(w * 0.80), int(h * 0.55))
print("flower area changed %.1f %%, far right %.1f %%" % (100 * flower, 100 * right))
if flower < 0.10: print("FAIL the snapshot does not show the strokes"); sys.exit(1)
if right > 0.01: print("FAIL pixels changed far from the strokes"); sys.exit(1)
PY
else
  echo "note: no python3, pixel check left to the gtest KioskApp.RecordedVisitor*"
fi
[ "$fail" -eq 0 ] && echo "ok   snapshot shows the strokes"
exit $fail

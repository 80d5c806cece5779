#!/usr/bin/env bash
# The emboss command: help on every subcommand, exit codes 0/1/2, eval and render from a scene.
set -u
bin="$1"; src="$2"
emboss="$bin/emboss"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
check() {  # check NAME EXPECTED_RC COMMAND...
  local name="$1" want="$2"; shift 2
  "$@" >"$tmp/out" 2>"$tmp/err"; local rc=$?
  if [ "$rc" -ne "$want" ]; then echo "FAIL $name: exit $rc, wanted $want"; cat "$tmp/out" "$tmp/err"; fail=1; else echo "ok   $name"; fi
}
cat >"$tmp/s.json" <<'JSON'
{"format":"emboss-scene","version":1,"workpiece":{"type":"plate","w":10,"h":8,"d":0.5},
 "operations":[{"op":"punch","side":"back","a":2,"p":0.5,"q":1,"at":[0,0,0.5]}]}
JSON
for sub in "" eval render export bench; do check "help $sub" 0 "$emboss" $sub --help; done
check "no subcommand" 2 "$emboss"
# The bench's smoke run: its table holds the in-run baseline and every piece's ratio to it.
check "bench --quick" 0 "$emboss" bench --quick --threads 2
grep -q '^Baseline (same run, same threads): a plain interval-pruning 2D renderer' "$tmp/out" &&
  grep -q '| / baseline |' "$tmp/out" && [ "$(grep -c '^| A4 plate | .* | [0-9.]*x | ' "$tmp/out")" -eq 2 ] &&
  grep -q '| region update ms (worst) |' "$tmp/out" && grep -Eq 'found a row at a time in [A-Z0-9_]+ lanes' "$tmp/out" &&
  [ "$(grep -c ' | yes |$' "$tmp/out")" -eq "$(grep -c '^| [Adpv][^|]* | [0-9]* | ' "$tmp/out")" ] &&
  { [ ! -r /proc/stat ] || grep -Eq '^Host, while the baseline and the pieces ran: steal [0-9.]+ % of its CPU time' "$tmp/out"; } ||
  { echo "FAIL bench table: $(head -c 600 "$tmp/out")"; fail=1; }
check "bench --only no piece" 2 "$emboss" bench --quick --only nonsense
grep -q "names no piece" "$tmp/err" || { echo "FAIL bench --only message: $(cat "$tmp/err")"; fail=1; }
check "unknown option" 2 "$emboss" render "$tmp/s.json" -o "$tmp/x.png" --bogus
check "bad size" 2 "$emboss" render "$tmp/s.json" -o "$tmp/x.png" --size 12
check "missing scene" 1 "$emboss" eval "$tmp/none.json" 0 0 0
grep -q "cannot open the scene file" "$tmp/err" || { echo "FAIL missing scene message"; fail=1; }
echo '{"version":1,,}' >"$tmp/bad.json"
check "malformed scene" 1 "$emboss" render "$tmp/bad.json" -o "$tmp/x.png"
grep -q "bad.json:1:14: not valid JSON" "$tmp/err" || { echo "FAIL malformed message: $(cat "$tmp/err")"; fail=1; }
# f at the punch's peak: the sheet rises by p a = 1 mm, so the front face is at z = 1.5.
check "eval point" 0 "$emboss" eval "$tmp/s.json" 0 0 1.5
[ "$(cat "$tmp/out")" = "0" ] || { echo "FAIL eval value $(cat "$tmp/out")"; fail=1; }
check "eval not a number" 2 "$emboss" eval "$tmp/s.json" nan 0 0
grep -q "must be finite" "$tmp/err" || { echo "FAIL eval nan message: $(cat "$tmp/err")"; fail=1; }
printf '0 0 1.5\ninf 0 0\n' >"$tmp/pts"
check "eval points not finite" 1 "$emboss" eval "$tmp/s.json" --points "$tmp/pts"
grep -q "pts:2: expected three finite numbers" "$tmp/err" || { echo "FAIL eval points inf: $(cat "$tmp/err")"; fail=1; }
printf '0 0 1.5\n# a comment\n0 0 1.0\n20 0 0\n' >"$tmp/pts"
check "eval points" 0 "$emboss" eval "$tmp/s.json" --points "$tmp/pts"
[ "$(wc -l <"$tmp/out")" -eq 3 ] || { echo "FAIL eval points count"; fail=1; }
[ "$(sed -n 2p "$tmp/out")" = "0.5" ] || { echo "FAIL eval mid-sheet $(sed -n 2p "$tmp/out")"; fail=1; }
check "render" 0 "$emboss" render "$tmp/s.json" -o "$tmp/x.png" --size 64x40 --stats
grep -q "mean steps per ray" "$tmp/out" || { echo "FAIL --stats output"; fail=1; }
[ -s "$tmp/x.png" ] || { echo "FAIL no png"; fail=1; }
check "render unwritable" 1 "$emboss" render "$tmp/s.json" -o "$tmp/no/such/dir/x.png" --size 32x20
check "export pov" 0 "$emboss" export "$tmp/s.json" --format pov -o "$tmp/x.pov"
grep -q "#declare Emboss_Function = function(x, y, z)" "$tmp/x.pov" || { echo "FAIL pov declares"; fail=1; }
grep -q "#ifndef (Emboss_Declare_Only)" "$tmp/x.pov" || { echo "FAIL pov declare-only guard"; fail=1; }
check "export bad format" 2 "$emboss" export "$tmp/s.json" --format obj -o "$tmp/x.obj"
# The take-home exports: admesh finds nothing to repair in the STL, lib3mf writes the 3MF, the
# height map is a 16-bit greyscale PNG.
check "export stl" 0 "$emboss" export "$tmp/s.json" --format stl -o "$tmp/x.stl" --resolution 0.25
grep -q "^mesh: .* triangles" "$tmp/out" || { echo "FAIL stl summary"; fail=1; }
if command -v admesh >/dev/null; then
  admesh "$tmp/x.stl" >"$tmp/admesh" 2>&1 || { echo "FAIL admesh exit"; fail=1; }
  for k in "Number of parts *: *1\b" "Degenerate facets *: *0\b" "Edges fixed *: *0\b" "Facets removed *: *0\b" \
           "Facets added *: *0\b" "Facets reversed *: *0\b" "Backwards edges *: *0\b" "Normals fixed *: *0\b" "Total disconnected facets *: *0 "; do
    grep -Eq "$k" "$tmp/admesh" || { echo "FAIL admesh: no '$k'"; cat "$tmp/admesh"; fail=1; }
  done
else
  echo "# admesh not installed: the STL's repair check skipped"
fi
check "export 3mf" 0 "$emboss" export "$tmp/s.json" --format 3mf -o "$tmp/x.3mf" --resolution 0.3
[ "$(head -c 2 "$tmp/x.3mf")" = "PK" ] || { echo "FAIL 3mf is not a zip"; fail=1; }
# A slicer opens both: PrusaSlicer's own mesh check (manifold, one part).
if command -v prusa-slicer >/dev/null; then
  for f in x.stl x.3mf; do
    timeout 120 prusa-slicer --info "$tmp/$f" >"$tmp/ps" 2>&1
    grep -q "^manifold = yes" "$tmp/ps" && grep -Eq "^number_of_parts = +1$" "$tmp/ps" ||
      { echo "FAIL prusa-slicer on $f: $(grep -E 'manifold|parts|rror' "$tmp/ps" | head -3)"; fail=1; }
  done
else
  echo "# prusa-slicer not installed: the slicer check skipped"
fi
check "export heightmap" 0 "$emboss" export "$tmp/s.json" --format heightmap -o "$tmp/h.png" --resolution 0.2
file "$tmp/h.png" | grep -q "16-bit grayscale" || { echo "FAIL heightmap: $(file "$tmp/h.png")"; fail=1; }
check "export postcard" 0 "$emboss" export "$tmp/s.json" --format postcard -o "$tmp/card.png"
file "$tmp/card.png" | grep -q "1800 x 1200" || { echo "FAIL postcard: $(file "$tmp/card.png")"; fail=1; }
check "export stl too fine" 1 "$emboss" export "$tmp/s.json" --format stl -o "$tmp/fine.stl" --resolution 0.001
grep -q "too fine" "$tmp/err" || { echo "FAIL too fine: $(cat "$tmp/err")"; fail=1; }
[ -e "$tmp/fine.stl" ] && { echo "FAIL a refused export left a file"; fail=1; }
check "export stl unwritable" 1 "$emboss" export "$tmp/s.json" --format stl -o "$tmp/no/such/dir/x.stl"
# Outputs that are not regular files are written in place, never renamed over: the standard output
# (the command's own lines then on standard error), a named pipe, a device (a full one an error,
# and still the device after), and through a symbolic link its target, the link kept.
check "render to stdout" 0 "$emboss" render "$tmp/s.json" -o - --size 64x40
file "$tmp/out" | grep -q "PNG image data, 64 x 40" && grep -q "^wrote -" "$tmp/err" ||
  { echo "FAIL render -o -: $(file "$tmp/out"); $(cat "$tmp/err")"; fail=1; }
check "export stl to stdout" 0 "$emboss" export "$tmp/s.json" --format stl -o - --resolution 0.5
# (A binary STL: 84 bytes of header and count, then 50 a triangle.)
triangles="$(od -An -tu4 -j80 -N4 "$tmp/out" | tr -d ' ')"
[ "${triangles:-0}" -gt 0 ] && [ "$(stat -c %s "$tmp/out")" -eq $((84 + 50 * triangles)) ] && grep -q "^wrote -" "$tmp/err" ||
  { echo "FAIL stl on stdout: $triangles triangles, $(stat -c %s "$tmp/out") bytes"; fail=1; }
# (lib3mf writes a named file: the package is made in the temporary folder, then copied out, then removed.)
mkdir "$tmp/t"
check "export 3mf to stdout" 0 env TMPDIR="$tmp/t" "$emboss" export "$tmp/s.json" --format 3mf -o - --resolution 0.5
[ "$(head -c 2 "$tmp/out")" = "PK" ] && grep -q "^wrote -" "$tmp/err" && [ -z "$(ls -A "$tmp/t")" ] ||
  { echo "FAIL 3mf on stdout: $(head -c 2 "$tmp/out"); $(ls -A "$tmp/t")"; fail=1; }
check "export studio to stdout" 2 "$emboss" export "$tmp/s.json" --format studio -o -
mkfifo "$tmp/pipe"
cat "$tmp/pipe" >"$tmp/from-pipe.png" & reader=$!
check "render to a pipe" 0 "$emboss" render "$tmp/s.json" -o "$tmp/pipe" --size 64x40
wait $reader
[ -p "$tmp/pipe" ] && file "$tmp/from-pipe.png" | grep -q "PNG image data, 64 x 40" ||
  { echo "FAIL pipe: $(ls -l "$tmp/pipe"); $(file "$tmp/from-pipe.png")"; fail=1; }
if [ -c /dev/full ]; then
  check "render to a full device" 1 "$emboss" render "$tmp/s.json" -o /dev/full --size 64x40
  grep -q "cannot write '/dev/full': No space left on device" "$tmp/err" && [ -c /dev/full ] && [ ! -e /dev/full.part ] ||
    { echo "FAIL /dev/full: $(cat "$tmp/err"); $(ls -l /dev/full)"; fail=1; }
  check "export pov to a full device" 1 "$emboss" export "$tmp/s.json" --format pov -o /dev/full
  [ -c /dev/full ] || { echo "FAIL /dev/full replaced"; fail=1; }
fi
check "render to /dev/null" 0 "$emboss" render "$tmp/s.json" -o /dev/null --size 32x20
[ -c /dev/null ] || { echo "FAIL /dev/null replaced"; fail=1; }
mkdir "$tmp/keep" && echo old >"$tmp/keep/real.png"
ln -sf keep/real.png "$tmp/link.png"
check "render through a link" 0 "$emboss" render "$tmp/s.json" -o "$tmp/link.png" --size 64x40
[ -L "$tmp/link.png" ] && file "$tmp/keep/real.png" | grep -q "PNG image data, 64 x 40" &&
  [ -z "$(ls "$tmp/keep" | grep -v '^real.png$')" ] ||
  { echo "FAIL link: $(ls -l "$tmp/link.png" "$tmp/keep")"; fail=1; }
exit $fail

#!/usr/bin/env bash
# The metals against a path tracer: for each metal, the same piece rendered by emboss and by
# Blender's Cycles (Debian's blender) on the exported mesh, lit by the exported studio, side by side.
#   bash tests/reference/metal-reference.sh BUILD_DIR [OUT_DIR] [WxH] [SAMPLES] [SCENE]
#     OUT_DIR   where reference-<metal>.png go (default docs/images)
#     WxH       picture size of each half (default 800x500); SAMPLES Cycles' samples a pixel (256)
#     SCENE     the piece (default firmware-app/pieces/2-shell.json); its metal is replaced in turn,
#               its tinge and patina strokes are left out (python3 edits the JSON)
# Needs blender (apt-get install blender); exits 77 without it. Minutes: about one a metal at the
# defaults on 2 cores.
set -euo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:?usage: metal-reference.sh BUILD_DIR [OUT_DIR] [WxH] [SAMPLES] [SCENE]}"
out="${2:-$top/docs/images}"
size="${3:-800x500}"
samples="${4:-256}"
scene="${5:-$top/firmware-app/pieces/2-shell.json}"
emboss="$build/firmware-app/emboss"
say() { echo "metal-reference: $*" >&2; }
command -v blender >/dev/null || { say "no blender (apt-get install blender) -- skipped"; exit 77; }
[ -x "$emboss" ] || { say "no $emboss: build first"; exit 2; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
say "mesh of $(basename "$scene")"
"$emboss" export "$scene" --format stl --resolution 0.15 -o "$work/piece.stl" | head -1 >&2
for metal in copper brass silver aluminium; do
  # The bare metal: no tinge, no patina strokes (the reference compares the metal's optics).
  python3 - "$scene" "$metal" > "$work/$metal.json" <<'PY' || { say "cannot read $scene"; exit 2; }
import json, sys
scene = json.load(open(sys.argv[1]))
scene["metal"], scene["tinge"] = sys.argv[2], "none"
scene["operations"] = [op for op in scene.get("operations", []) if op.get("op") != "patina"]
json.dump(scene, sys.stdout)
PY
  t0=$SECONDS
  "$emboss" render "$work/$metal.json" -o "$work/ours-$metal.png" --size "$size" >/dev/null
  t1=$SECONDS
  "$emboss" export "$work/$metal.json" --format studio -o "$work/studio-$metal.hdr" >/dev/null
  blender -b --factory-startup -P "$top/tests/reference/cycles_reference.py" -- "$work/studio-$metal.json" \
    "$work/piece.stl" "$out/reference-$metal.png" "$size" "$samples" "$work/ours-$metal.png" > "$work/blender.log" 2>&1 ||
    { tail -20 "$work/blender.log" >&2; exit 1; }
  say "$metal: emboss $((t1 - t0)) s, Cycles $((SECONDS - t1)) s ($samples samples) -> $out/reference-$metal.png"
done

#!/usr/bin/env bash
# Sets up a Debian 12 machine (apt-get), builds, and runs the kiosk: a window on a desktop, else a
# few seconds of headless attract mode that write a snapshot.
set -euo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$top"
bash platform/debian/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
if [ -x build/firmware-app/emboss-kiosk ]; then
  if [ -n "${DISPLAY:-}" ]; then
    exec build/firmware-app/emboss-kiosk --display=x11 "$@"
  fi
  build/firmware-app/emboss-kiosk --display=auto --attract --run-for=8 --snapshot=out/kiosk.png "$@"
  echo "snapshot of the kiosk: $top/out/kiosk.png"
else
  build/firmware-app/emboss render docs/examples/medallion.json -o out/sample.png --size 1280x800
  echo "rendered: $top/out/sample.png"
fi

#!/usr/bin/env bash
# Builds the Debian package: a Release build in BUILD_DIR (default build-deb beside the sources),
# then `cpack -G DEB`; prints the path of the .deb it made (BUILD_DIR/package/emboss_<ver>_<arch>.deb).
#   bash platform/debian/make-deb.sh [BUILD_DIR]
# Extra CMake options come from EMBOSS_CMAKE_ARGS (e.g. a toolchain file, see cross-arm64.sh).
# Install it with: sudo apt-get install ./emboss_<ver>_<arch>.deb (docs/install.md).
set -euo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$top/build-deb}"
case "$build" in /*) ;; *) build="$PWD/$build" ;; esac
cd "$top"
bash platform/debian/install-deps.sh >&2
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# The package needs no tests; EMBOSS_TESTS=OFF also keeps GoogleTest out of the build.
# shellcheck disable=SC2086
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX=/usr -DEMBOSS_TESTS=OFF \
  "${launcher[@]}" ${EMBOSS_CMAKE_ARGS:-} >&2
cmake --build "$build" -j "${EMBOSS_JOBS:-$(nproc)}" >&2
rm -f "$build"/package/emboss_*.deb
(cd "$build" && cpack -G DEB >&2)
deb="$(ls "$build"/package/emboss_*.deb)"
[ -f "$deb" ] || { echo "make-deb: cpack made no .deb in $build/package" >&2; exit 1; }
echo "$deb"

#!/usr/bin/env bash
# Sets up a Debian 12 machine (apt-get), builds everything and runs every test, then the fuzzers briefly.
set -euo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$top"
bash platform/debian/install-deps.sh
# The cross compiler, qemu-user and the arm64 libraries for the arm64 test (tests/arm64/neon.sh).
bash platform/debian/cross-arm64.sh --set-up
jobs="$(nproc)"

# ccache (outside the checkout, ~/.cache/ccache) keyed by paths relative to the checkout: a rerun,
# or another clone of the same sources, compiles only what changed.
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$top" CCACHE_NOHASHDIR=1
fi

echo "== build (RelWithDebInfo)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEMBOSS_BOOT_TEST=ON "${launcher[@]}" >/dev/null
cmake --build build -j "$jobs"

echo "== tests"
# Hardware tests skip with a message where no device is attached; hil tests run in a VM (tests/hil).
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 900

echo "== fuzzers (libFuzzer, clang; ${EMBOSS_FUZZ_SECONDS:-20} s each)"
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DEMBOSS_FUZZ=ON "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j "$jobs"
bash tests/fuzz/run-fuzzers.sh build-fuzz "${EMBOSS_FUZZ_SECONDS:-20}"

# The closing line of the whole run, counted from CTest's own summary.
summary="$(ctest --test-dir build -N | tail -1)"
echo "all tests and fuzzers done ($summary)"

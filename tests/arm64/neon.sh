#!/usr/bin/env bash
# The board's instruction set, under qemu-user: `emboss` and the unit tests built for arm64 (the
# toolchain of platform/debian/cross-arm64.sh) and run as on a Raspberry Pi 4 (qemu's cortex-a72:
# NEON and no SVE, so Highway picks its NEON lanes, as on the board). What it shows is correctness
# only: the SIMD rows against the points one at a time bit for bit, dirty updates against full
# frames (the unit tests, and the bench's own check), the bench's table made to its end. Emulated
# times say nothing about the board's.
#   bash tests/arm64/neon.sh BUILD_DIR SOURCE_DIR [GTEST_FILTER]
# The cross build goes to BUILD_DIR/arm64 (ccache makes a rerun quick). Exits 77 when the cross
# compiler or qemu-user is missing: `bash platform/debian/cross-arm64.sh --set-up` installs them.
set -uo pipefail
build="$1/arm64"; top="$2"
# The tests of what has SIMD lanes or must be the same bits on any instruction set: the rows of
# SIMD (LeafBounds, PathRows, ShadeLanes, FieldLanes), the field and its updates, the shading, dirty
# updates against full frames. A test takes 20 to 50 times as long under qemu as natively: the whole
# suite is left to platform/debian/cross-arm64.sh.
filter="${3:-LeafBounds.*:WalkLanes.*:RayLanes.*:Srgb8.ChannelsInLanes*:PathRows.*:ShadeLanes.*:FieldLanes.*:Shading.*:FieldSync.*:HeightField.IncrementalUpdatesEqualAFullBuildBitForBit:HeightField.ErrorAgainstTheExactSumIsSmall:DirtyRegion.SheetPlateEqualsFullRender:DirtyRegion.SheetVmOutlineEqualsFullRender:DirtyRegion.ATangleOfBlendBeadsEndsAsAFullRender}"
say() { echo "arm64: $*" >&2; }
command -v aarch64-linux-gnu-g++ >/dev/null || { say "no aarch64-linux-gnu-g++ (bash platform/debian/cross-arm64.sh --set-up) -- skipped"; exit 77; }
qemu="$(command -v qemu-aarch64-static || command -v qemu-aarch64)" || { say "no qemu-user (bash platform/debian/cross-arm64.sh --set-up) -- skipped"; exit 77; }
cpu=(-cpu cortex-a72)
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
t0=$SECONDS
if ! cmake -S "$top" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEMBOSS_BOOT_TEST=OFF \
     -DCMAKE_TOOLCHAIN_FILE="$top/platform/debian/toolchain-arm64.cmake" "${launcher[@]}" >"$build.configure.log" 2>&1; then
  tail -20 "$build.configure.log" >&2
  say "FAIL: the arm64 build does not configure (the arm64 -dev packages: bash platform/debian/cross-arm64.sh --set-up)"
  exit 1
fi
cmake --build "$build" --target emboss emboss_tests -j "$(nproc)" >"$build.build.log" 2>&1 ||
  { grep -E "error|Error" "$build.build.log" | head -20 >&2; say "FAIL: the arm64 build"; exit 1; }
file -L "$build/firmware-app/emboss" | grep -q "ARM aarch64" || { say "FAIL: emboss is not an arm64 program"; exit 1; }
say "built for arm64 in $((SECONDS - t0)) s"
fail=0

# The unit tests (not the slow, golden or hardware ones), as on the board's cores.
t0=$SECONDS
"$qemu" "${cpu[@]}" "$build/tests/emboss_tests" --gtest_brief=1 \
  --gtest_filter="$filter:-*Hardware*:*Slow*:*Golden*" >"$build.tests.log" 2>&1
rc=$?
grep -E "^\[  (FAILED|PASSED|SKIPPED) " "$build.tests.log" | sort -u | head -30 >&2
passed=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) tests\?\.$/\1/p' "$build.tests.log")
if [ $rc -ne 0 ] || [ "${passed:-0}" -lt 10 ]; then
  grep -B5 "FAILED" "$build.tests.log" | head -60 >&2
  say "FAIL: the unit tests under qemu ($(basename "$qemu") ${cpu[*]}), exit $rc"; fail=1
fi
say "unit tests under qemu ${cpu[*]}: ${passed:-0} passed in $((SECONDS - t0)) s"

# The bench's smoke run: NEON lanes, and its strokes' dirty updates leave a full frame's bytes.
t0=$SECONDS
"$qemu" "${cpu[@]}" "$build/firmware-app/emboss" bench --quick --threads 2 >"$build.bench.txt" 2>"$build.bench.err"
rc=$?
rows=$(grep -c '^| [Adpv][^|]* | [0-9]* | ' "$build.bench.txt")
exact=$(grep -c ' | yes |$' "$build.bench.txt")
grep -o "found a row at a time in [A-Z0-9_]* lanes" "$build.bench.txt" | head -1 >&2
if [ $rc -ne 0 ] || [ "$rows" -lt 5 ] || [ "$exact" -ne "$rows" ] || ! grep -q "found a row at a time in NEON lanes" "$build.bench.txt"; then
  cat "$build.bench.txt" "$build.bench.err" | head -40 >&2
  say "FAIL: the bench under qemu: exit $rc, $rows pieces, $exact with dirty = full, lanes above"; fail=1
fi
say "bench --quick under qemu ${cpu[*]}: $((SECONDS - t0)) s, $rows pieces, dirty = full on $exact"
exit $fail

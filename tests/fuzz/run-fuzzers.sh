#!/bin/bash
# Runs each fuzz target of tests/fuzz for a while from its seeds; exit 1 when any of them reports.
#   run-fuzzers.sh BUILD_FUZZ_DIR [SECONDS]     (from the top of the checkout; run-tests.sh calls it)
set -uo pipefail
dir=${1:?usage: run-fuzzers.sh BUILD_FUZZ_DIR [SECONDS]}
seconds=${2:-20}
fuzz_failed=0
# One run per target in tests/fuzz (a stale binary of a removed target is not run). A crash, a
# sanitizer report (the build stops at the first: -fno-sanitize-recover=all) or a time-out ends
# libFuzzer with a non-zero status; a report in the log fails the run as well.
for src in tests/fuzz/fuzz_*.cpp; do
  name="$(basename "$src" .cpp)"
  f="$dir/$name"
  [ -x "$f" ] || { echo "fuzz: $name was not built"; fuzz_failed=1; continue; }
  corpus="$dir/corpus-$name"
  mkdir -p "$corpus"
  seeds="tests/fuzz/seeds/${name#fuzz_}"
  [ -d "$seeds" ] || seeds=""
  if "$f" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$dir/$name-" "$corpus" $seeds \
      >"$dir/$name.log" 2>&1 &&
     ! grep -q 'runtime error:\|ERROR: AddressSanitizer\|ERROR: libFuzzer\|SUMMARY: ' "$dir/$name.log"; then
    echo "fuzz: $name ok ($(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/$name.log") runs)"
  else
    echo "fuzz: $name FAILED"; tail -40 "$dir/$name.log"; fuzz_failed=1
  fi
done
[ "$fuzz_failed" -eq 0 ] || { echo "fuzzing found a crash"; exit 1; }

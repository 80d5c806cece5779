#!/usr/bin/env bash
# --version on every program: "NAME VERSION" with the project's version (and the git description
# when built in a checkout), exit 0, nothing on stderr.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
version="$(sed -n 's/^project(emboss VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")"
[ -n "$version" ] || { echo "FAIL: no project version in CMakeLists.txt"; exit 1; }
fail=0
found=0
for prog in emboss emboss-kiosk emboss-input embossctl; do
  [ -x "$bin/$prog" ] || { [ "$prog" = embossctl ] && continue; echo "FAIL $prog not built"; fail=1; continue; }
  found=$((found + 1))
  "$bin/$prog" --version >"$tmp/out" 2>"$tmp/err"; rc=$?
  line="$(head -1 "$tmp/out")"
  if [ "$rc" -ne 0 ]; then echo "FAIL $prog --version: exit $rc"; cat "$tmp/out" "$tmp/err"; fail=1; continue; fi
  if ! printf '%s\n' "$line" | grep -Eqx "$prog ${version//./\\.}( \(git [^)]+\))?"; then
    echo "FAIL $prog --version: '$line', wanted '$prog $version' and maybe '(git ...)'"; fail=1; continue
  fi
  [ -s "$tmp/err" ] && { echo "FAIL $prog --version wrote to stderr: $(cat "$tmp/err")"; fail=1; continue; }
  echo "ok   $prog --version: $line"
done
[ "$found" -ge 3 ] || { echo "FAIL only $found programs"; fail=1; }
exit $fail

#!/usr/bin/env bash
# The kiosk keeps its metals' shading tables in its cache folder between starts: the first start
# computes and keeps them, the next reads them, and the picture is the same byte for byte either
# way; a broken file is named and replaced, a folder that cannot be written only costs time, and
# systemd's CACHE_DIRECTORY comes before XDG_CACHE_HOME.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0
demo="$src/tests/app/data/visitor-demo.events"
run() {  # run NAME [VAR=VALUE...]: a replay with the cache environment given, snapshot NAME.png
  local name=$1; shift
  env -u CACHE_DIRECTORY -u XDG_CACHE_HOME HOME="$tmp/home" "$@" "$kiosk" --display=headless --size 200x125 \
    --sessions-dir "$tmp/sessions-$name" --pieces "$src/firmware-app/pieces" --staff-socket none --log-level debug \
    --tablet="evemu:$demo" --fast --snapshot="$tmp/$name.png" >"$tmp/$name.out" 2>"$tmp/$name.err"
  local rc=$?
  if [ "$rc" -ne 0 ] && grep -q "headless:" "$tmp/$name.err"; then echo "skip: no headless display here"; exit 77; fi
  [ "$rc" -eq 0 ] || { echo "FAIL $name: exit $rc"; cat "$tmp/$name.err"; fail=1; }
}
same() {  # same NAME: its snapshot equals the first run's
  cmp -s "$tmp/first.png" "$tmp/$1.png" || { echo "FAIL $1: the picture differs from the first run's"; fail=1; }
}
cache="$tmp/cache/emboss"

run first XDG_CACHE_HOME="$tmp/cache"
kept=$(grep -c "tables: .* kept in $cache/" "$tmp/first.err")
n=$(ls "$cache"/*.table 2>/dev/null | wc -l)
[ "$kept" -ge 2 ] && [ "$n" -eq "$kept" ] || { echo "FAIL first: $kept tables said kept, $n files"; cat "$tmp/first.err"; fail=1; }
grep -q "irradiance kept" "$tmp/first.err" || { echo "FAIL first: no irradiance table kept"; fail=1; }
echo "ok   the first start computes $kept tables and keeps them"

run again XDG_CACHE_HOME="$tmp/cache"
read=$(grep -c "tables: .* read from $cache/" "$tmp/again.err")
[ "$read" -eq "$kept" ] || { echo "FAIL again: $read tables read, wanted $kept"; cat "$tmp/again.err"; fail=1; }
grep -q "kept in" "$tmp/again.err" && { echo "FAIL again: tables computed again"; fail=1; }
same again
echo "ok   the next start reads them all; the same picture"

# Broken files: one cut short, one with a byte changed; then one that is not a table at all.
files=("$cache"/*.table)
truncate -s 1000 "${files[0]}"
printf '\x01' | dd of="${files[1]}" bs=1 seek=5000 conv=notrunc status=none
run broken XDG_CACHE_HOME="$tmp/cache"
grep -q "${files[0]} is broken (the wrong size\|${files[0]} is broken (cut short" "$tmp/broken.err" ||
  { echo "FAIL broken: the cut file is not named"; cat "$tmp/broken.err"; fail=1; }
grep -q "${files[1]} is broken (a bad checksum)" "$tmp/broken.err" || { echo "FAIL broken: the changed byte is not found"; cat "$tmp/broken.err"; fail=1; }
same broken
echo "not a table" > "${files[0]}"
run foreign XDG_CACHE_HOME="$tmp/cache"
grep -q "${files[0]} is broken (not a table file" "$tmp/foreign.err" || { echo "FAIL foreign: the foreign file is not named"; cat "$tmp/foreign.err"; fail=1; }
same foreign
run mended XDG_CACHE_HOME="$tmp/cache"
[ "$(grep -c "read from $cache/" "$tmp/mended.err")" -eq "$kept" ] || { echo "FAIL mended: the broken files were not replaced"; cat "$tmp/mended.err"; fail=1; }
same mended
echo "ok   broken files are named, computed again and replaced; the same picture"

# A cache folder that cannot be made (a file stands where it should be): said once, the kiosk goes on.
echo "a file" > "$tmp/blocked"
run blocked XDG_CACHE_HOME="$tmp/blocked"
[ "$(grep -c "cannot keep them in $tmp/blocked/emboss" "$tmp/blocked.err")" -eq 1 ] ||
  { echo "FAIL blocked: the unwritable cache is not said exactly once"; cat "$tmp/blocked.err"; fail=1; }
same blocked
echo "ok   an unwritable cache folder is said once; the same picture"

# systemd's CacheDirectory= (CACHE_DIRECTORY) first, then XDG_CACHE_HOME, then HOME's .cache.
run unit CACHE_DIRECTORY="$tmp/unit" XDG_CACHE_HOME="$tmp/elsewhere"
[ "$(ls "$tmp/unit"/*.table 2>/dev/null | wc -l)" -eq "$kept" ] && [ ! -e "$tmp/elsewhere/emboss" ] ||
  { echo "FAIL unit: CACHE_DIRECTORY not used"; fail=1; }
run home
[ "$(ls "$tmp/home/.cache/emboss"/*.table 2>/dev/null | wc -l)" -eq "$kept" ] || { echo "FAIL home: HOME/.cache/emboss not used"; fail=1; }
same unit; same home
echo "ok   CACHE_DIRECTORY, else XDG_CACHE_HOME, else HOME/.cache"
exit $fail

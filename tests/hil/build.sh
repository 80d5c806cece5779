#!/bin/bash
# build.sh BUILD_DIR SOURCE_DIR [NAME...]: compiles the HIL test programs and helpers (tests/hil/*.cpp) with the
# compiler directly, against BUILD_DIR's libemboss_platform.a and libemboss_core.a and the pkg-config
# libraries of the platform back ends. Programs go to $HIL_OUT (default BUILD_DIR/hil); each is
# recompiled only when a file it includes changed, relinked when a library did. HIL_EXTRA_OBJS:
# objects linked ahead of the libraries (mutate.sh links a deliberately broken back end that way).
set -u -o pipefail
build=$(cd "$1" && pwd) || exit 2
src=$(cd "$2" && pwd) || exit 2
shift 2
out=${HIL_OUT:-$build/hil}
mkdir -p "$out"
CXX=${CXX:-g++}
plat="$build/platform/libemboss_platform.a"
core="$build/libemboss_core.a"
for lib in "$plat" "$core"; do
  [ -f "$lib" ] || { echo "build.sh: $lib is missing: build the project first (ninja -C $build emboss_tests emboss-input)" >&2; exit 2; }
done
pkgs="hidapi-hidraw libusb-1.0 libgpiod libevdev libudev libsystemd libpng libjpeg sqlite3 zlib"
# The display back ends live in the same archive; link their libraries too when they are there.
for p in egl glesv2 gbm libdrm osmesa x11 freetype2; do pkg-config --exists "$p" 2>/dev/null && pkgs="$pkgs $p"; done
cflags=$(pkg-config --cflags $pkgs) || exit 2
libs=$(pkg-config --libs $pkgs) || exit 2

names=("$@")
if [ ${#names[@]} -eq 0 ]; then
  for f in "$src"/tests/hil/*.cpp; do names+=("$(basename "$f" .cpp)"); done
fi

# Compiles when the source or a header it includes (from the .d file g++ writes) is newer than the
# object; links when the object or a library is newer than the program.
build_one() {
  local name=$1 cpp="$src/tests/hil/$1.cpp" bin="$out/$1" obj="$out/$1.o" dep="$out/$1.d"
  [ -f "$cpp" ] || { echo "build.sh: no $cpp" >&2; return 2; }
  local compile=1
  if [ -f "$obj" ] && [ -f "$dep" ]; then
    local inputs
    inputs=$(sed -e 's/^[^:]*://' -e 's/\\$//' "$dep" | tr ' ' '\n' | grep -v '^$')
    # shellcheck disable=SC2086
    [ -z "$(find $inputs -newer "$obj" 2>/dev/null | head -1)" ] && [ "$(echo "$inputs" | wc -l)" -gt 1 ] && compile=0
  fi
  if [ $compile = 1 ]; then
    # shellcheck disable=SC2086
    if ! $CXX -std=c++20 -O1 -g -Wall -Wextra -Wno-unused-parameter -DGLM_FORCE_CXX17 \
        -I"$src/src" -I"$src/platform" -I"$src/tests/hil" $cflags -MMD -MF "$dep" -c -o "$obj" "$cpp" 2> "$out/$name.build.log"; then
      echo "build.sh: $name did not compile:" >&2
      head -40 "$out/$name.build.log" >&2
      rm -f "$obj"
      return 1
    fi
  fi
  if [ -x "$bin" ] && [ -z "${HIL_EXTRA_OBJS:-}" ] && [ -z "$(find "$obj" "$plat" "$core" -newer "$bin" 2>/dev/null | head -1)" ]; then
    return 0
  fi
  # shellcheck disable=SC2086
  if ! $CXX -o "$bin.tmp" "$obj" ${HIL_EXTRA_OBJS:-} "$plat" "$core" $libs -lpthread -ldl 2> "$out/$name.link.log"; then
    echo "build.sh: $name did not link:" >&2
    head -40 "$out/$name.link.log" >&2
    rm -f "$bin.tmp"
    return 1
  fi
  mv "$bin.tmp" "$bin"
}

rc=0
pids=()
for n in "${names[@]}"; do
  build_one "$n" &
  pids+=($!)
  if [ ${#pids[@]} -ge "${HIL_JOBS:-2}" ]; then wait "${pids[0]}" || rc=1; pids=("${pids[@]:1}"); fi
done
for p in "${pids[@]}"; do wait "$p" || rc=1; done
exit $rc

#!/usr/bin/env bash
# Builds emboss for 64-bit ARM boards on a Debian 12 amd64 machine, runs the unit tests under
# qemu-user (the GoogleTest label unit; the shell tests need binfmt and are left out), and makes
# the arm64 .deb; prints its path.
#   bash platform/debian/cross-arm64.sh [BUILD_DIR]     (default build-arm64 beside the sources)
#   bash platform/debian/cross-arm64.sh --set-up        (only the set-up below; the test command runs
#                                                        it for tests/arm64/neon.sh)
# Set-up (once, with apt-get): the arm64 architecture for dpkg, crossbuild-essential-arm64,
# qemu-user-static and the arm64 twins of the -dev packages the build links (multiarch, installed
# beside the amd64 ones). EMBOSS_ARM64_TESTS=0 skips the tests.
set -euo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
set_up_only=0
[ "${1:-}" = --set-up ] && { set_up_only=1; shift; }
build="${1:-$top/build-arm64}"
case "$build" in /*) ;; *) build="$PWD/$build" ;; esac
cd "$top"
log() { echo "cross-arm64: $*" >&2; }
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

# ---- set-up: what the build needs, for arm64 (the tools and header-only packages are shared)
arm64_dev=(libgtest-dev libgmock-dev libhwy-dev libpng-dev libsqlite3-dev zlib1g-dev lib3mf-dev libmeshoptimizer-dev libjpeg62-turbo-dev libfreetype-dev libegl-dev libgles-dev
           libgbm-dev libdrm-dev libosmesa6-dev libx11-dev libsystemd-dev libgpiod-dev libusb-1.0-0-dev
           libhidapi-dev libevdev-dev libudev-dev)
host_tools=(crossbuild-essential-arm64 qemu-user-static pkg-config cmake ninja-build git help2man dpkg-dev file
            nlohmann-json3-dev libcli11-dev libglm-dev)
wanted=("${host_tools[@]}" "${arm64_dev[@]/%/:arm64}")
missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    log "adding the arm64 architecture to dpkg"
    $sudo dpkg --add-architecture arm64
  fi
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -q >&2
  $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi
[ $set_up_only = 1 ] && { log "set up: ${#wanted[@]} packages present"; exit 0; }

# ---- build (as packaged: release-flags.cmake), with the tests
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -C platform/debian/release-flags.cmake -S . -B "$build" -G Ninja \
  -DCMAKE_TOOLCHAIN_FILE="$top/platform/debian/toolchain-arm64.cmake" "${launcher[@]}" >&2
cmake --build "$build" -j "${EMBOSS_JOBS:-$(nproc)}" >&2
file "$build/firmware-app/emboss-kiosk" | grep -q "ARM aarch64" || { log "emboss-kiosk is not an arm64 program"; exit 1; }

# ---- the unit tests under qemu-user (CTest puts the emulator in front of every test program)
if [ "${EMBOSS_ARM64_TESTS:-1}" != 0 ]; then
  log "unit tests under $(basename "$(sed -n 's/^EMBOSS_QEMU_AARCH64:FILEPATH=//p' "$build/CMakeCache.txt")")"
  ctest --test-dir "$build" -L unit -j "${EMBOSS_JOBS:-$(nproc)}" --output-on-failure --timeout 900 >&2
fi

# ---- the package: dpkg-shlibdeps must look at arm64 libraries
rm -f "$build"/package/emboss_*.deb
(cd "$build" && eval "$(dpkg-architecture -aarm64 -s 2>/dev/null)" && cpack -G DEB >&2)
deb="$(ls "$build"/package/emboss_*_arm64.deb)"
echo "$deb"

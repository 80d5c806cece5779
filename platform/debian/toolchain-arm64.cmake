# Cross-compiling for 64-bit ARM boards (Raspberry Pi 4/5, Debian 12 / Raspberry Pi OS bookworm) on
# a Debian 12 amd64 machine: crossbuild-essential-arm64 and the arm64 -dev packages (multiarch),
# set up by platform/debian/cross-arm64.sh. Programs built for the board run here under qemu-user.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(EMBOSS_TRIPLET aarch64-linux-gnu)

set(CMAKE_C_COMPILER ${EMBOSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${EMBOSS_TRIPLET}-g++)
set(CMAKE_STRIP ${EMBOSS_TRIPLET}-strip CACHE FILEPATH "")
set(CMAKE_OBJCOPY ${EMBOSS_TRIPLET}-objcopy CACHE FILEPATH "")
# GCC's notes that passing some structs changed ABI in GCC 10.1: everything here is built by GCC 12.
# Appended after the cache (which release-flags.cmake sets), once: CMake reads this file twice on
# the first configure and once on later ones, and changed flags would rebuild everything.
if(NOT CMAKE_CXX_FLAGS MATCHES "-Wno-psabi")
  string(APPEND CMAKE_CXX_FLAGS " -Wno-psabi")
endif()

# Headers and libraries of the board from the multiarch folders; programs (pkg-config, git) from
# here, pkg-config looking only at the arm64 .pc files.
set(CMAKE_LIBRARY_ARCHITECTURE ${EMBOSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${EMBOSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig")

# Tests, test discovery and help2man run the arm64 programs through qemu-user; the arm64 loader
# and libraries are the multiarch ones the -dev packages installed, so no -L is needed.
find_program(EMBOSS_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64)
if(EMBOSS_QEMU_AARCH64)
  # As a Raspberry Pi 4's core: NEON and no SVE, so Highway picks the board's own lanes (qemu's
  # default CPU has SVE2, which no Pi has).
  set(CMAKE_CROSSCOMPILING_EMULATOR ${EMBOSS_QEMU_AARCH64} -cpu cortex-a72)
endif()

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

# Headers and libraries of the board from the multiarch folders; programs (pkg-config, git) from here.
set(CMAKE_LIBRARY_ARCHITECTURE ${EMBOSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${EMBOSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig")
set(PKG_CONFIG_EXECUTABLE ${EMBOSS_TRIPLET}-pkg-config CACHE FILEPATH "")

# Tests, test discovery and help2man run the arm64 programs through qemu-user; the arm64 loader
# and libraries are the multiarch ones the -dev packages installed, so no -L is needed.
find_program(EMBOSS_QEMU_AARCH64 NAMES qemu-aarch64-static qemu-aarch64)
if(EMBOSS_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${EMBOSS_QEMU_AARCH64})
endif()

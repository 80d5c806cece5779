# Initial cache (cmake -C) for the packaged builds (make-deb.sh, cross-arm64.sh): Release, installed
# under /usr, with Debian's hardening flags (as dpkg-buildflags gives them with hardening=+all):
# stack protector, fortified libc calls, read-only relocations bound at start. FORCE: an existing
# build folder takes them too.
set(CMAKE_BUILD_TYPE Release CACHE STRING "" FORCE)
set(CMAKE_INSTALL_PREFIX /usr CACHE PATH "" FORCE)
set(CMAKE_C_FLAGS "-fstack-protector-strong -D_FORTIFY_SOURCE=2" CACHE STRING "" FORCE)
set(CMAKE_CXX_FLAGS "-fstack-protector-strong -D_FORTIFY_SOURCE=2" CACHE STRING "" FORCE)
set(CMAKE_EXE_LINKER_FLAGS "-Wl,-z,relro -Wl,-z,now" CACHE STRING "" FORCE)

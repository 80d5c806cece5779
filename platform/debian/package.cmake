# The Debian package (cpack -G DEB in the build folder; platform/debian/make-deb.sh does it all).
# Only the install component "kiosk" goes in: never the test binary or build tools.
# EMBOSS_MAINTAINER: platform/debian/install.cmake.

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME emboss)
set(CPACK_PACKAGE_VENDOR "emboss")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${EMBOSS_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "museum kiosk for virtual metal embossing")
set(CPACK_PACKAGE_DESCRIPTION "Visitors emboss a virtual copper, brass, silver or aluminium sheet with a
pressure pen: trace the contours, raise the relief from behind with punches,
beat the background down, colour the metal. The model is a function
representation ray traced on the CPU; after each stroke only the affected
region of the screen is traced again.
.
The package holds the kiosk (emboss-kiosk, run by emboss-kiosk.service on the
board's screen through DRM/KMS), the command line (emboss) and the tablet tool
(emboss-input), the udev rules that give the kiosk its tablets, GPIO buttons
and camera, its user and groups, and the attract pieces.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_INSTALL_CMAKE_PROJECTS "${PROJECT_BINARY_DIR};${PROJECT_NAME};kiosk;/")
set(CPACK_STRIP_FILES ON)
set(CPACK_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/package)

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # emboss_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${EMBOSS_MAINTAINER}")
if(CMAKE_CROSSCOMPILING AND CMAKE_SYSTEM_PROCESSOR STREQUAL "aarch64")
  set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE arm64)
endif()
# The libraries from the binaries (dpkg-shlibdeps); the rest is what the kiosk needs at run time:
# systemd (sysusers, tmpfiles, the unit), udev (the rules), Mesa's EGL and DRI drivers (GBM on KMS,
# llvmpipe where the board has no GPU driver) and the overlay's font.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "systemd, udev, libegl-mesa0, libgl1-mesa-dri, fonts-dejavu-core")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
# The maintainer scripts do what debhelper's dh_installsysusers, dh_installtmpfiles, dh_installudev
# and dh_installsystemd would generate. The configuration is a conffile: dpkg keeps the museum's
# edits over upgrades and asks before replacing them.
file(WRITE ${PROJECT_BINARY_DIR}/debian/conffiles "${CMAKE_INSTALL_FULL_SYSCONFDIR}/emboss/kiosk.conf\n")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${PROJECT_BINARY_DIR}/debian/conffiles
    ${PROJECT_SOURCE_DIR}/platform/debian/maintscripts/postinst
    ${PROJECT_SOURCE_DIR}/platform/debian/maintscripts/prerm
    ${PROJECT_SOURCE_DIR}/platform/debian/maintscripts/postrm)
include(CPack)

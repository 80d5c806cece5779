# Install rules (cmake --install, and the .deb of platform/debian/package.cmake). Everything the
# appliance needs is in the component "kiosk"; the test binary and the fuzzers have no install rule.
# With CMAKE_INSTALL_PREFIX=/usr (the package) the configuration goes to /etc/emboss.
include(GNUInstallDirs)

set(EMBOSS_COMPONENT kiosk)
# systemd and udev read from /usr/lib, not from the multiarch library folder.
set(EMBOSS_LIB ${CMAKE_INSTALL_PREFIX}/lib)

foreach(prog emboss emboss-kiosk emboss-input embossctl)
  if(TARGET ${prog})
    install(TARGETS ${prog} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${EMBOSS_COMPONENT})
  endif()
endforeach()

# The users, groups and paths: the unit, sysusers.d and tmpfiles.d are the single truth for them.
install(FILES ${PROJECT_SOURCE_DIR}/systemd/emboss-kiosk.service
        DESTINATION ${EMBOSS_LIB}/systemd/system COMPONENT ${EMBOSS_COMPONENT})
install(FILES ${PROJECT_SOURCE_DIR}/systemd/99-emboss-kiosk.rules
        DESTINATION ${EMBOSS_LIB}/udev/rules.d COMPONENT ${EMBOSS_COMPONENT})
install(FILES ${PROJECT_SOURCE_DIR}/systemd/emboss.sysusers RENAME emboss.conf
        DESTINATION ${EMBOSS_LIB}/sysusers.d COMPONENT ${EMBOSS_COMPONENT})
install(FILES ${PROJECT_SOURCE_DIR}/systemd/emboss.tmpfiles RENAME emboss.conf
        DESTINATION ${EMBOSS_LIB}/tmpfiles.d COMPONENT ${EMBOSS_COMPONENT})
install(FILES ${PROJECT_SOURCE_DIR}/systemd/system.conf.d/emboss-watchdog.conf
        DESTINATION ${EMBOSS_LIB}/systemd/system.conf.d COMPONENT ${EMBOSS_COMPONENT})

install(FILES ${PROJECT_SOURCE_DIR}/firmware-app/kiosk.conf
        DESTINATION ${CMAKE_INSTALL_FULL_SYSCONFDIR}/emboss COMPONENT ${EMBOSS_COMPONENT})
file(GLOB EMBOSS_PIECE_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/firmware-app/pieces/*.json)
install(FILES ${EMBOSS_PIECE_FILES} DESTINATION ${CMAKE_INSTALL_DATADIR}/emboss/pieces COMPONENT ${EMBOSS_COMPONENT})

# Documentation: the README and the docs (without their pictures), the copyright, a changelog.
file(GLOB EMBOSS_DOC_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/docs/*.md)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${EMBOSS_DOC_FILES} ${PROJECT_SOURCE_DIR}/platform/debian/copyright
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT ${EMBOSS_COMPONENT})
# The changelog's date: SOURCE_DATE_EPOCH, else the last commit's, so it changes with the sources only.
set(EMBOSS_MAINTAINER "emboss maintainers <emboss-maintainers@example.org>" CACHE STRING
    "The package's Maintainer field and changelog signature (set the museum's own)")
if(NOT DEFINED ENV{SOURCE_DATE_EPOCH} AND EXISTS ${PROJECT_SOURCE_DIR}/.git)
  execute_process(COMMAND git -C ${PROJECT_SOURCE_DIR} log -1 --format=%ct
                  OUTPUT_VARIABLE commit_time OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(commit_time MATCHES "^[0-9]+$")
    set(ENV{SOURCE_DATE_EPOCH} ${commit_time})
  endif()
endif()
string(TIMESTAMP EMBOSS_CHANGELOG_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
configure_file(${PROJECT_SOURCE_DIR}/platform/debian/changelog.in ${PROJECT_BINARY_DIR}/debian/changelog @ONLY)

# Man pages from each program's --help and --version (help2man), compressed as Debian wants them.
find_program(GZIP gzip REQUIRED)
add_custom_command(OUTPUT ${PROJECT_BINARY_DIR}/debian/changelog.gz
  COMMAND ${GZIP} -9nf -k ${PROJECT_BINARY_DIR}/debian/changelog
  DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog
  VERBATIM)
add_custom_target(emboss_changelog ALL DEPENDS ${PROJECT_BINARY_DIR}/debian/changelog.gz)
install(FILES ${PROJECT_BINARY_DIR}/debian/changelog.gz DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT ${EMBOSS_COMPONENT})

find_program(HELP2MAN help2man)
if(HELP2MAN)
  set(EMBOSS_MAN_PAGES "")
  file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/man)  # help2man writes there; not every generator makes it
  # program | section | the option that prints the whole help | one line for NAME. The sections
  # help2man cannot see (files, exit status, see also) are in platform/debian/man/PROGRAM.h2m.
  foreach(entry "emboss|1|--help-all|render, evaluate and export virtual embossing scenes"
                "emboss-kiosk|8|--help|the virtual metal embossing exhibit"
                "emboss-input|1|--help|look at pen tablets: descriptors, recordings, live devices"
                "embossctl|8|--help|the staff tool of the emboss kiosk: status, sessions, export, reset, wipe")
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 prog)
    list(GET entry 1 section)
    list(GET entry 2 help_option)
    list(GET entry 3 what)
    set(include ${PROJECT_SOURCE_DIR}/platform/debian/man/${prog}.h2m)
    if(NOT TARGET ${prog})
      continue()
    endif()
    set(page ${PROJECT_BINARY_DIR}/man/${prog}.${section})
    # Cross builds run the program under the emulator through a small wrapper.
    set(runner $<TARGET_FILE:${prog}>)
    if(CMAKE_CROSSCOMPILING_EMULATOR)
      set(runner ${PROJECT_BINARY_DIR}/man/run-${prog})
      list(JOIN CMAKE_CROSSCOMPILING_EMULATOR " " emulator)
      file(GENERATE OUTPUT ${runner} CONTENT "#!/bin/sh\nexec ${emulator} $<TARGET_FILE:${prog}> \"$@\"\n"
           FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
    endif()
    add_custom_command(OUTPUT ${page}.gz
      COMMAND ${HELP2MAN} --no-info --no-discard-stderr --section=${section} --name=${what}
              --help-option=${help_option} --include=${include}
              --manual=emboss --source=emboss --output=${page} ${runner}
      COMMAND ${GZIP} -9nf ${page}
      DEPENDS ${prog} ${include}
      COMMENT "man page ${prog}(${section})"
      VERBATIM)
    list(APPEND EMBOSS_MAN_PAGES ${page}.gz)
    install(FILES ${page}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man${section} COMPONENT ${EMBOSS_COMPONENT})
  endforeach()
  add_custom_target(emboss_man ALL DEPENDS ${EMBOSS_MAN_PAGES})
else()
  message(STATUS "help2man not found: no man pages (platform/debian/install-deps.sh installs help2man)")
endif()

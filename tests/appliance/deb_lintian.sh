#!/usr/bin/env bash
# lintian on the package: no errors and no warnings (info and pedantic tags are listed, and the
# accepted ones explained in docs/install.md).
#   deb_lintian.sh BUILD_DIR_OF_make-deb.sh
set -u
deb="$(ls "$1"/package/emboss_*.deb 2>/dev/null | head -1)"
[ -n "$deb" ] || { echo "FAIL no package in $1/package (the appliance.deb test makes it)"; exit 1; }
command -v lintian >/dev/null || { echo "skip: lintian is not installed (apt-get install lintian)"; exit 77; }
lintian --info --pedantic --fail-on error,warning "$deb" 2>&1 | grep -v "running with root privileges"
rc=${PIPESTATUS[0]}
[ "$rc" -eq 0 ] && echo "ok   lintian: no errors or warnings on $(basename "$deb")" || echo "FAIL lintian found errors or warnings (above)"
exit "$rc"

#!/usr/bin/env bash
# Installs the package the way a fresh Debian 12 board gets it -- `apt-get install ./emboss_*.deb` --
# in a throwaway Debian 12 chroot (minbase, made by mmdebstrap), then checks that the programs run,
# the user and groups exist, the files are in place and the service is enabled; then remove keeps
# the visitors' sessions and purge deletes them.
#   bash platform/debian/test-deb-install.sh DEB|FOLDER_WITH_THE_DEB
#   bash platform/debian/test-deb-install.sh --build BUILD_DIR   (make-deb.sh BUILD_DIR first)
# The chroot's tarball is cached in ~/.cache/emboss-pkg/ (EMBOSS_PKG_CACHE), keyed by a hash of
# the suite, mirror and package list; it already holds the .deb's dependencies, so a run needs no
# network once the cache is warm. Exit 77 (skipped) without root, mmdebstrap or the Debian mirror.
set -uo pipefail
top="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
skip() { echo "skip: $*"; exit 77; }
die() { echo "FAIL: $*"; exit 1; }

if [ "${1:-}" = "--build" ]; then
  [ -n "${2:-}" ] || die "--build needs a build folder"
  deb="$(bash "$top/platform/debian/make-deb.sh" "$2" 2>"$2.make-deb.log")" || { tail -30 "$2.make-deb.log"; die "make-deb.sh failed"; }
else
  deb="${1:-}"
  # A folder: the package in it (the CTest test passes make-deb.sh's package folder).
  [ -d "$deb" ] && deb="$(ls "$deb"/emboss_*.deb 2>/dev/null | head -1)"
fi
[ -n "$deb" ] && [ -f "$deb" ] || die "no package: give DEB or --build BUILD_DIR (got '${deb}')"
deb="$(cd "$(dirname "$deb")" && pwd)/$(basename "$deb")"
[ "$(id -u)" -eq 0 ] || skip "needs root (chroot and mounts)"
command -v mmdebstrap >/dev/null || skip "mmdebstrap is not installed (apt-get install mmdebstrap)"
arch="$(dpkg-deb -f "$deb" Architecture)"
[ "$arch" = "$(dpkg --print-architecture)" ] || skip "a $arch package on a $(dpkg --print-architecture) machine"

# ---- the chroot's tarball: minbase plus the package's dependencies, cached by a hash of what it holds
mirror="${EMBOSS_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
depends="$(dpkg-deb -f "$deb" Depends | tr ',' '\n' | sed -e 's/([^)]*)//g' -e 's/|.*//' -e 's/[[:space:]]//g' | sed '/^$/d' | sort -u | paste -sd, -)"
cache="${EMBOSS_PKG_CACHE:-$HOME/.cache/emboss-pkg}"
key="$(printf 'v1 bookworm minbase %s %s %s' "$arch" "$mirror" "$depends" | sha256sum | cut -c1-16)"
tarball="$cache/bookworm-minbase-$arch-$key.tar"
mkdir -p "$cache"
if [ ! -s "$tarball" ]; then
  echo "== making the Debian 12 chroot (once; cached as $tarball)"
  started=$SECONDS
  part="$cache/partial-$key.tar"  # mmdebstrap picks the format by the name's ending
  if ! mmdebstrap --variant=minbase --include="$depends" --skip=cleanup/apt/lists \
      bookworm "$part" "deb $mirror bookworm main" >"$cache/mmdebstrap.log" 2>&1; then
    rm -rf "$part"
    tail -5 "$cache/mmdebstrap.log"
    skip "mmdebstrap could not make a Debian 12 chroot (no network to $mirror?); log: $cache/mmdebstrap.log"
  fi
  mv "$part" "$tarball"
  echo "   made in $((SECONDS - started)) s"
  # Older tarballs of other keys are of no use any more.
  find "$cache" -name 'bookworm-minbase-*.tar' ! -name "$(basename "$tarball")" -delete
fi

root="$(mktemp -d /tmp/emboss-deb-test.XXXXXX)"
cleanup() {
  for m in proc dev/pts dev; do umount "$root/$m" 2>/dev/null; done
  rm -rf --one-file-system "$root"
}
trap cleanup EXIT
tar -C "$root" -xf "$tarball" || die "cannot unpack $tarball"
mount --bind /dev "$root/dev" && mount --bind /dev/pts "$root/dev/pts" && mount -t proc proc "$root/proc" ||
  skip "cannot mount /dev and /proc into the chroot (a container without mount rights?)"
cp "$deb" "$root/tmp/"
in_root() { chroot "$root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 DEBIAN_FRONTEND=noninteractive "$@"; }

fail=0
check() {  # check NAME COMMAND... (run in the chroot; prints its output on failure)
  local name="$1"; shift
  if out="$(in_root "$@" 2>&1)"; then echo "ok   $name"; else echo "FAIL $name:"; echo "$out" | tail -20; fail=1; fi
}
expect() {  # expect NAME CONDITION_IN_SH (run in the chroot)
  check "$1" sh -c "$2"
}

echo "== apt-get install ./$(basename "$deb")"
started=$SECONDS
if ! in_root apt-get install -y -q --no-download /tmp/"$(basename "$deb")" >"$root.apt.log" 2>&1; then
  # Without --no-download: a dependency newer than the cached chroot's comes from the mirror.
  in_root apt-get install -y -q /tmp/"$(basename "$deb")" >>"$root.apt.log" 2>&1 || { tail -30 "$root.apt.log"; rm -f "$root.apt.log"; die "apt-get install failed"; }
fi
grep -E "^(W|E): |emboss: " "$root.apt.log"; rm -f "$root.apt.log"
echo "   installed in $((SECONDS - started)) s"
ver="$(dpkg-deb -f "$deb" Version)"

expect "dpkg says installed" "dpkg-query -W -f='\${Status}' emboss | grep -qx 'install ok installed'"
check "emboss-kiosk --help" emboss-kiosk --help
for p in emboss emboss-kiosk emboss-input; do
  expect "$p --version" "$p --version | grep -q '^$p $ver'"
done
[ -x "$root/usr/bin/embossctl" ] && expect "embossctl --version" "embossctl --version | grep -q '$ver'"
check "emboss --help" emboss --help
check "emboss-input --help" emboss-input --help
check "the shipped config passes --check-config" emboss-kiosk --check-config
expect "a bad config fails --check-config, naming the line" \
  "printf 'metal = gold\n' >/tmp/bad.conf; ! emboss-kiosk --check-config /tmp/bad.conf 2>/tmp/err && grep -q '^/tmp/bad.conf:1: metal' /tmp/err"
check "emboss renders an attract piece (the libraries load)" \
  emboss render /usr/share/emboss/pieces/1-rosette.json -o /tmp/rosette.png --size 96x64
expect "user emboss-kiosk" "getent passwd emboss-kiosk | grep -q ':/var/lib/emboss-kiosk:/usr/sbin/nologin$'"
expect "groups emboss and emboss-staff" "getent group emboss >/dev/null && getent group emboss-staff >/dev/null"
expect "export folder from tmpfiles.d" "[ \"\$(stat -c '%U:%G %a' /media/emboss-export)\" = 'emboss-kiosk:emboss-staff 2750' ]"
for f in /usr/lib/systemd/system/emboss-kiosk.service /usr/lib/udev/rules.d/99-emboss-kiosk.rules \
         /usr/lib/sysusers.d/emboss.conf /usr/lib/tmpfiles.d/emboss.conf \
         /usr/lib/systemd/system.conf.d/emboss-watchdog.conf /etc/emboss/kiosk.conf \
         /usr/share/doc/emboss/copyright /usr/share/doc/emboss/install.md \
         /usr/share/man/man1/emboss.1.gz /usr/share/man/man8/emboss-kiosk.8.gz /usr/share/man/man1/emboss-input.1.gz; do
  expect "file $f" "[ -s $f ]"
done
expect "attract pieces" "[ \$(ls /usr/share/emboss/pieces/*.json | wc -l) -ge 3 ]"
expect "the config is a conffile" "dpkg-query -W -f='\${Conffiles}' emboss | grep -q /etc/emboss/kiosk.conf"
expect "no test programs installed" "! dpkg -L emboss | grep -Eq 'emboss_tests|fuzz_|gtest'"
expect "service enabled" "[ -L /etc/systemd/system/multi-user.target.wants/emboss-kiosk.service ]"
check "systemd-analyze verify the unit" systemd-analyze verify /usr/lib/systemd/system/emboss-kiosk.service

echo "== remove keeps the sessions, purge deletes them"
in_root sh -c 'mkdir -p /var/lib/emboss-kiosk/sessions && echo {} >/var/lib/emboss-kiosk/sessions/s.json'
check "apt-get remove" apt-get remove -y -q emboss
expect "sessions kept after remove" "[ -f /var/lib/emboss-kiosk/sessions/s.json ] && [ -f /etc/emboss/kiosk.conf ]"
check "apt-get purge" apt-get purge -y -q emboss
expect "sessions and config gone after purge" "[ ! -e /var/lib/emboss-kiosk ] && [ ! -e /etc/emboss/kiosk.conf ]"
expect "service link gone after purge" "[ ! -e /etc/systemd/system/multi-user.target.wants/emboss-kiosk.service ]"

[ "$fail" -eq 0 ] && echo "the package installs, runs and purges on Debian 12" || echo "the package has problems (above)"
exit "$fail"

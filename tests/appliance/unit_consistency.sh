#!/usr/bin/env bash
# The unit, sysusers.d and tmpfiles.d are the single truth for users, groups and paths: what the
# unit, the udev rules and the shipped config name must be declared there.
#   unit_consistency.sh SOURCE_DIR
set -u
src="$(cd "$1" && pwd)"
unit="$src/systemd/emboss-kiosk.service"
sysusers="$src/systemd/emboss.sysusers"
tmpfiles="$src/systemd/emboss.tmpfiles"
fail=0
say_fail() { echo "FAIL $*"; fail=1; }
value() { sed -n "s/^$1=//p" "$unit"; }  # value KEY: the unit's setting(s)

user="$(value User)"
grep -Eq "^u[[:space:]]+$user[[:space:]]" "$sysusers" && echo "ok   User=$user is in sysusers.d" || say_fail "User=$user not declared in $sysusers"
# Groups: declared by the package, or standard Debian system groups (from udev and base-passwd).
for g in $(value Group) $(value SupplementaryGroups); do
  case "$g" in video|render|input) echo "ok   group $g is a Debian system group"; continue ;; esac
  if grep -Eq "^g[[:space:]]+$g[[:space:]]" "$sysusers" || grep -Eq "^u[[:space:]]+$g[[:space:]]" "$sysusers"; then
    echo "ok   group $g is in sysusers.d"
  else
    say_fail "group $g (unit) not declared in $sysusers"
  fi
done
for g in $(sed -n 's/.*GROUP="\([^"]*\)".*/\1/p' "$src/systemd/99-emboss-kiosk.rules" | sort -u); do
  grep -Eq "^g[[:space:]]+$g[[:space:]]" "$sysusers" && echo "ok   udev group $g is in sysusers.d" || say_fail "udev rules' group $g not in $sysusers"
  value SupplementaryGroups | grep -qw "$g" || say_fail "udev rules' group $g is not among the unit's SupplementaryGroups"
done
# The home of the user is the unit's state folder.
state="/var/lib/$(value StateDirectory)"
grep -Eq "^u[[:space:]]+$user[[:space:]].*[[:space:]]$state[[:space:]]" "$sysusers" && echo "ok   home $state" || say_fail "$user's home in sysusers.d is not $state"
# Every writable path of the unit is made by tmpfiles.d, owned by the unit's user; the config's
# export_dir is that path.
for p in $(value ReadWritePaths); do
  p="${p#-}"
  grep -Eq "^d[[:space:]]+$p[[:space:]]+[0-7]+[[:space:]]+$user[[:space:]]" "$tmpfiles" && echo "ok   $p made by tmpfiles.d for $user" ||
    say_fail "ReadWritePaths=$p not made by $tmpfiles for $user"
  grep -Eq "^export_dir[[:space:]]*=[[:space:]]*$p[[:space:]]*$" "$src/firmware-app/kiosk.conf" && echo "ok   kiosk.conf exports to $p" ||
    say_fail "kiosk.conf's export_dir is not $p"
done
grep -q -- "--config=/etc/emboss/kiosk.conf" "$unit" && echo "ok   ExecStart reads /etc/emboss/kiosk.conf" || say_fail "ExecStart does not pass --config=/etc/emboss/kiosk.conf"
exit $fail

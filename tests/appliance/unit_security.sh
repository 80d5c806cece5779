#!/usr/bin/env bash
# The kiosk's unit stays hardened: `systemd-analyze security --offline` rates it at most 2.0 (on a
# scale of 10; the unhardened unit was 6.1). Also shows the check can fail: the same unit without
# its hardening section must be rated above the limit.
#   unit_security.sh SOURCE_DIR [LIMIT, default 2.0]
set -u
src="$(cd "$1" && pwd)"
limit="${2:-2.0}"
unit="$src/systemd/emboss-kiosk.service"
command -v systemd-analyze >/dev/null || { echo "skip: no systemd-analyze"; exit 77; }
systemd-analyze security --help 2>/dev/null | grep -q -- "--offline" || { echo "skip: systemd-analyze without --offline (systemd < 250)"; exit 77; }
threshold="$(awk -v l="$limit" 'BEGIN { printf "%d", l * 10 + 0.5 }')"  # --threshold counts tenths
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
fail=0

rate() {  # rate UNIT_FILE: prints the overall exposure; exit status of the threshold check
  systemd-analyze security --no-pager --offline=true --threshold="$threshold" "$1" >"$tmp/report" 2>&1; local rc=$?
  sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p' "$tmp/report"
  return $rc
}

if figure="$(rate "$unit")"; then
  echo "ok   emboss-kiosk.service: exposure $figure (limit $limit)"
else
  echo "FAIL emboss-kiosk.service: exposure ${figure:-?} above $limit:"
  grep -E "✗|Overall" "$tmp/report"
  fail=1
fi
[ -n "$figure" ] || { echo "FAIL no overall figure in the report:"; cat "$tmp/report"; fail=1; }

# The unit with everything from "# Hardening" to [Install] taken out must fail the same check.
mkdir -p "$tmp/weak"
sed '/^# Hardening/,/^\[Install\]/{/^\[Install\]/!d}' "$unit" >"$tmp/weak/emboss-kiosk.service"
if weak="$(rate "$tmp/weak/emboss-kiosk.service")"; then
  echo "FAIL the unit without its hardening passes too (exposure ${weak:-?}): the check cannot fail"; fail=1
else
  echo "ok   without its hardening the unit is rated ${weak:-?}, above the limit"
fi
exit $fail

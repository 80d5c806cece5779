#!/usr/bin/env bash
# The kiosk's log as journal entries, without journald: in a mount namespace of its own a stand-in
# listens at the journal's socket, the kiosk runs with JOURNAL_STREAM naming its stderr and replays a
# recording; every stroke's "journal: stroke N durable" must come as an entry with PRIORITY=7 and
# EMBOSS_SESSION, and nothing may reach stderr. Skipped (77) where a mount namespace cannot be made.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
command -v unshare >/dev/null && command -v python3 >/dev/null || { echo "skip: no unshare or python3"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
unshare --mount --propagation private true 2>/dev/null || { echo "skip: cannot make a mount namespace (not root?)"; exit 77; }
cat >"$tmp/inner.sh" <<'INNER'
set -u
tmp="$1"; kiosk="$2"; src="$3"
mkdir -p /run/systemd && mount -t tmpfs tmpfs /run/systemd || exit 77
mkdir -p /run/systemd/journal
python3 - "$tmp" <<'PY' &
import os, socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind("/run/systemd/journal/socket")
open(os.path.join(sys.argv[1], "ready"), "w").close()
with open(os.path.join(sys.argv[1], "entries"), "wb") as out:
    while True:
        d = s.recv(65536)
        if d == b"QUIT\n": break
        out.write(d.replace(b"\n", b"\t") + b"\n"); out.flush()
PY
py=$!
for _ in $(seq 100); do [ -e "$tmp/ready" ] && break; sleep 0.1; done
: >"$tmp/err"
export JOURNAL_STREAM="$(stat -c '%d:%i' "$tmp/err")"
"$kiosk" --display=headless --size 160x100 --threads 1 --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces" \
  --tablet="evemu:$src/tests/app/data/visitor-demo.events" --fast --staff-socket none --log-level=debug >"$tmp/out" 2>>"$tmp/err"
echo "kiosk exit $?" >"$tmp/rc"
python3 -c 'import socket; s=socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM); s.sendto(b"QUIT\n", "/run/systemd/journal/socket")'
wait $py
INNER
unshare --mount --propagation private bash "$tmp/inner.sh" "$tmp" "$kiosk" "$src"
rc=$?
[ $rc -eq 77 ] && { echo "skip: cannot mount a tmpfs on /run/systemd"; exit 77; }
fail=0
bad() { echo "FAIL $*"; fail=1; }
grep -q 'kiosk exit 0' "$tmp/rc" 2>/dev/null || { bad "the kiosk did not exit 0: $(cat "$tmp/rc" 2>/dev/null)"; cat "$tmp/err"; }
[ -s "$tmp/entries" ] || bad "no journal entries"
durable=$(grep -c 'MESSAGE=journal: stroke [0-9]* durable' "$tmp/entries")
[ "$durable" -ge 1 ] || bad "no 'journal: stroke N durable' entries"
tagged=$(grep 'MESSAGE=journal: stroke [0-9]* durable' "$tmp/entries" | grep 'PRIORITY=7' | grep -c $'\tEMBOSS_SESSION=[1-9][0-9]*\t')
[ "$tagged" -eq "$durable" ] || { bad "$durable durable entries, $tagged with PRIORITY=7 and EMBOSS_SESSION"; head -3 "$tmp/entries"; }
grep 'MESSAGE=display: ' "$tmp/entries" | grep -q 'EMBOSS_SESSION' && bad "a line about no session carries EMBOSS_SESSION"
grep -q 'SYSLOG_IDENTIFIER=emboss-kiosk' "$tmp/entries" || bad "no SYSLOG_IDENTIFIER"
[ -s "$tmp/err" ] && { bad "lines went to stderr as well"; head -3 "$tmp/err"; }
[ $fail -eq 0 ] && echo "ok   kiosk journal fields: $durable durable strokes, each with PRIORITY=7 and EMBOSS_SESSION"
exit $fail

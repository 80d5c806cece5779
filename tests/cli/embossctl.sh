#!/usr/bin/env bash
# embossctl against a running kiosk (headless, a recording replayed): status, sessions, an export
# (refused on the root file system, done with --allow-any-dir, its progress shown as it goes, every
# file fsynced and readable; without "progress" in the request, the answer alone), reset, wipe, bad
# requests and a kiosk that is not there.
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"; ctl="$bin/embossctl"
[ -x "$kiosk" ] && [ -x "$ctl" ] || { echo "skip: no emboss-kiosk or embossctl"; exit 77; }
tmp="$(mktemp -d)"; trap 'kill $pid 2>/dev/null; rm -rf "$tmp"' EXIT
fail=0
bad() { echo "FAIL $*"; fail=1; }
sock="$tmp/staff.sock"
mkdir -p "$tmp/dest" "$tmp/dest2" "$tmp/sessions"
# Three sessions saved earlier (a scene file each, one with a picture): the export copies four with
# the one in progress.
for n in 1 2 3; do
  cp "$src/firmware-app/pieces/1-rosette.json" "$tmp/sessions/session-20240101-12000$n.json"
done
printf 'not really a png' >"$tmp/sessions/session-20240101-120001.png"
"$kiosk" --display=headless --size 160x100 --threads 1 --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces" \
  --tablet="evemu:$src/tests/app/data/visitor-demo.events" --staff-socket "$sock" --run-for 60 >"$tmp/out" 2>"$tmp/err" &
pid=$!
for _ in $(seq 100); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] || { bad "no socket at $sock"; cat "$tmp/err"; exit 1; }
[ "$(stat -c %a "$sock")" = 660 ] || bad "the socket's mode is $(stat -c %a "$sock"), not 660"
# Wait until the visitor has made something.
for _ in $(seq 150); do "$ctl" --socket "$sock" status 2>/dev/null | grep -q 'operations_on_bench: [1-9]' && break; sleep 0.1; done
"$ctl" --socket "$sock" status >"$tmp/status" || bad "status failed"
grep -q '^state: visitor' "$tmp/status" || { bad "status does not say visitor"; cat "$tmp/status"; }
grep -q 'journal: ok' "$tmp/status" || bad "status does not show the journal"
grep -q 'free_mib' "$tmp/status" || bad "status does not show the disk"
"$ctl" --socket "$sock" --json sessions | grep -q '"journal":\[{' || bad "sessions lists no journalled session"
# The root file system is not a stick.
if "$ctl" --socket "$sock" export "$tmp/dest" 2>"$tmp/e1"; then bad "export onto the root file system was accepted"; fi
grep -q "not a stick" "$tmp/e1" || { bad "the refusal does not say why"; cat "$tmp/e1"; }
"$ctl" --socket "$sock" export --allow-any-dir "$tmp/dest" >"$tmp/x" 2>"$tmp/xp" || { bad "export failed"; cat "$tmp/x" "$tmp/xp"; }
# Progress as it goes, on stderr: from 0/4 to 4/4 sessions, the bytes growing.
grep -Eq '^export: 0/4 sessions, [0-9]+\.[0-9] MB$' "$tmp/xp" || { bad "no progress line at the start"; cat "$tmp/xp"; }
[ "$(grep '^export: ' "$tmp/xp" | tail -1 | sed 's/,.*//')" = "export: 4/4 sessions" ] || { bad "the last progress line is not 4/4"; cat "$tmp/xp"; }
[ "$(grep -c '^export: ' "$tmp/xp")" -ge 2 ] || bad "fewer than two progress lines"
grep -q '^files: 6$' "$tmp/x" || { bad "the export did not copy 6 files (3 scenes, a picture, the session in progress and its picture)"; cat "$tmp/x"; }
folder=$(sed -n 's/^folder: //p' "$tmp/x")
[ -d "$folder" ] || bad "no export folder"
case "$folder" in "$tmp/dest"/emboss-sessions-*) ;; *) bad "exported outside DEST: $folder" ;; esac
ls "$folder"/current-*.json >/dev/null 2>&1 || bad "the session in progress was not exported"
grep -q '"op"' "$folder"/current-*.json || bad "the exported session has no operations"
[ -z "$(find "$tmp/dest" -name '*.part')" ] || bad "temporary files left in DEST"
# A client that does not ask for progress gets the answer alone, one line.
printf '{"cmd":"export","dest":"%s","allow_any_dir":true}\n' "$tmp/dest2" | timeout 60 python3 -c '
import socket,sys
s=socket.socket(socket.AF_UNIX); s.connect(sys.argv[1]); s.sendall(sys.stdin.buffer.read())
data=b""
while True:
    b=s.recv(4096)
    if not b: break
    data+=b
sys.stdout.write(data.decode())' "$sock" >"$tmp/raw2"
[ "$(wc -l <"$tmp/raw2")" -eq 1 ] && grep -q '"ok":true' "$tmp/raw2" || { bad "an export without progress did not answer with one line"; cat "$tmp/raw2"; }
[ -z "$(find "$tmp/dest" "$tmp/dest2" -mindepth 1 -maxdepth 1 ! -name 'emboss-sessions-*')" ] || bad "something other than the export folders in DEST"
"$ctl" --socket "$sock" reset | grep -q 'session_ended: true' || bad "reset did not end the visitor's session"
grep -q 'state: session-ended (now attract)' "$tmp/err" || bad "reset did not return the kiosk to attract mode"
ls "$tmp/sessions"/session-*.json >/dev/null 2>&1 || bad "reset did not save the session"
"$ctl" --socket "$sock" wipe --older-than 0 | grep -q 'wiped: [1-9]' || bad "wipe deleted nothing"
ls "$tmp/sessions"/session-*.json >/dev/null 2>&1 && bad "wipe left the finished session's file"
"$ctl" --socket "$sock" wipe 2>/dev/null; [ $? -eq 2 ] || bad "wipe without --older-than is not a usage error"
printf '{"cmd":"format-disk"}\n' | timeout 20 python3 -c '
import socket,sys; s=socket.socket(socket.AF_UNIX); s.connect(sys.argv[1]); s.sendall(sys.stdin.buffer.read()); print(s.recv(4096).decode())' "$sock" >"$tmp/raw"
grep -q '"ok":false' "$tmp/raw" || { bad "an unknown command was not refused"; cat "$tmp/raw"; }
kill -TERM $pid; wait $pid; rc=$?
[ $rc -eq 0 ] || bad "the kiosk exited $rc on SIGTERM"
[ -e "$sock" ] && bad "the socket was left behind"
"$ctl" --socket "$sock" status 2>"$tmp/e2"; [ $? -eq 1 ] || bad "no kiosk: not exit 1"
grep -q "is emboss-kiosk running" "$tmp/e2" || bad "no kiosk: the message does not say so"
# take_home in the config: the export makes a postcard and a height map beside each session.
mkdir -p "$tmp/s2" "$tmp/dest3"
cp "$src/firmware-app/pieces/1-rosette.json" "$tmp/s2/session-20240101-130000.json"
printf 'take_home = postcard, heightmap\n' >"$tmp/k2.conf"
"$kiosk" --config "$tmp/k2.conf" --display=headless --size 160x100 --threads 1 --sessions-dir "$tmp/s2" \
  --pieces "$src/firmware-app/pieces" --tablet=none --staff-socket "$tmp/s2.sock" --run-for 120 >"$tmp/out2" 2>"$tmp/err2" &
pid=$!
for _ in $(seq 100); do [ -S "$tmp/s2.sock" ] && break; sleep 0.1; done
"$ctl" --socket "$tmp/s2.sock" export --allow-any-dir "$tmp/dest3" >"$tmp/x3" 2>&1 || { bad "take-home export failed"; cat "$tmp/x3"; }
grep -q '^files: 3$' "$tmp/x3" || { bad "the take-home export did not write 3 files (the scene, its postcard, its height map)"; cat "$tmp/x3" "$tmp/err2"; }
f3=$(sed -n 's/^folder: //p' "$tmp/x3")
file "$f3"/session-20240101-130000.postcard.png 2>/dev/null | grep -q "1800 x 1200" || bad "no postcard beside the session"
file "$f3"/session-20240101-130000.height.png 2>/dev/null | grep -q "16-bit grayscale" || bad "no height map beside the session"
kill -TERM $pid; wait $pid
[ $fail -eq 0 ] && echo "ok   embossctl: status, sessions, export, reset, wipe, refusals, take-home files"
exit $fail

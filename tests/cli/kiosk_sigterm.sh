#!/usr/bin/env bash
# SIGTERM in every state and display back end: the kiosk exits 0 within a second, the visitor's
# session is durable (its scene file written, every stroke it had reported durable in it).
# States: starting (before the first frame), attract, a visitor drawing, the staff screen, an export
# under way. Back ends: headless, osmesa, and x11 when Xvfb is installed. kms is tested in the VM
# (tests/hil/kms.sh), where the emulated CPU makes the time meaningless; on this machine's CPU the
# kiosk's own work on SIGTERM is what is timed here.
#   kiosk_sigterm.sh BIN_DIR SOURCE_DIR       EMBOSS_SIGTERM_LIMIT=SECONDS (default 1.0)
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"; ctl="$bin/embossctl"
[ -x "$kiosk" ] && [ -x "$ctl" ] || { echo "skip: no emboss-kiosk or embossctl"; exit 77; }
limit=${EMBOSS_SIGTERM_LIMIT:-1.0}
tmp="$(mktemp -d)"
xpid=""
trap '[ -n "$xpid" ] && kill "$xpid" 2>/dev/null; rm -rf "$tmp"' EXIT
fail=0
demo="$src/tests/app/data/visitor-demo.events"

backends=(headless osmesa)
xdisplay=""
if command -v Xvfb >/dev/null; then
  # -displayfd: Xvfb takes a free display number and writes it there once it is ready.
  Xvfb -displayfd 3 -screen 0 800x600x24 -nolisten tcp 3>"$tmp/xdisplay" >/dev/null 2>&1 &
  xpid=$!
  for _ in $(seq 100); do [ -s "$tmp/xdisplay" ] && break; sleep 0.1; done
  xdisplay=":$(head -1 "$tmp/xdisplay" 2>/dev/null)"
  [ "$xdisplay" != ":" ] && backends+=(x11) || echo "note: Xvfb did not start; x11 not tested"
else
  echo "note: no Xvfb; x11 not tested"
fi

# Waits until FILE has a line matching RE (at most $3 seconds).
wait_for() {
  local re=$1 file=$2 n=$(( ${3:-30} * 10 ))
  for _ in $(seq "$n"); do grep -Eq "$re" "$file" 2>/dev/null && return 0; sleep 0.1; done
  return 1
}

# One case: start, bring the kiosk into STATE, SIGTERM, time the exit.
one() {
  local display=$1 state=$2 dir="$tmp/$1-$2"
  mkdir -p "$dir/sessions" "$dir/dest"
  local args=(--display="$display" --size 640x400 --sessions-dir "$dir/sessions" --pieces "$src/firmware-app/pieces"
              --staff-socket "$dir/staff.sock" --log-level=debug --session-out "$dir/out.json")
  case "$state" in
    visitor) args+=(--tablet="evemu:$demo") ;;
    staff) args+=(--tablet=none --staff) ;;
    *) args+=(--tablet=none) ;;
  esac
  if [ "$state" = exporting ]; then  # enough sessions that the export is still under way when the signal comes
    for n in $(seq -w 1 300); do cp "$src/firmware-app/pieces/1-rosette.json" "$dir/sessions/session-20240101-120$n.json"; done
  fi
  DISPLAY=$xdisplay "$kiosk" "${args[@]}" >"$dir/out" 2>"$dir/err" &
  local pid=$!
  case "$state" in
    starting) sleep 0.3 ;;
    attract | staff) wait_for 'first frame on the screen' "$dir/err" 60 || { echo "FAIL $display $state: no first frame"; tail -3 "$dir/err"; fail=1; } ;;
    visitor) wait_for 'journal: stroke [0-9]+ durable' "$dir/err" 60 || { echo "FAIL $display $state: no stroke made"; tail -3 "$dir/err"; fail=1; } ;;
    exporting)
      wait_for 'first frame on the screen' "$dir/err" 60
      "$ctl" --socket "$dir/staff.sock" export --allow-any-dir "$dir/dest" >"$dir/x" 2>"$dir/xp" &
      wait_for '^export: [0-9]+/' "$dir/xp" 30 || { echo "FAIL $display $state: the export did not start"; cat "$dir/x" "$dir/xp"; fail=1; }
      ;;
  esac
  if ! kill -0 "$pid" 2>/dev/null; then
    wait "$pid"; echo "FAIL $display $state: the kiosk stopped by itself (exit $?)"; tail -5 "$dir/err"; fail=1; return
  fi
  local t0 t1 rc
  t0=$(date +%s%N)
  kill -TERM "$pid"
  wait "$pid"; rc=$?
  t1=$(date +%s%N)
  local ms=$(( (t1 - t0) / 1000000 ))
  local verdict=ok
  [ "$rc" -eq 0 ] || { verdict=FAIL; echo "FAIL $display $state: exit $rc on SIGTERM"; tail -5 "$dir/err"; }
  awk -v ms="$ms" -v lim="$limit" 'BEGIN { exit !(ms / 1000.0 <= lim) }' ||
    { verdict=FAIL; echo "FAIL $display $state: $ms ms from SIGTERM to exit (limit $limit s)"; }
  if [ "$state" = visitor ]; then
    # The strokes reported durable are in the scene file written at exit and in the saved session.
    local durable saved ops
    durable=$(sed -n 's/.*journal: stroke \([0-9]*\) durable.*/\1/p' "$dir/err" | sort -n | tail -1)
    saved=$(ls "$dir"/sessions/session-*.json 2>/dev/null | head -1)
    ops=$(grep -o '"op"' "$dir/out.json" 2>/dev/null | wc -l)
    grep -q 'session: saving (the kiosk is stopping)' "$dir/err" || { verdict=FAIL; echo "FAIL $display $state: the session was not saved"; }
    [ -n "$saved" ] || { verdict=FAIL; echo "FAIL $display $state: no session file in the sessions folder"; }
    [ "${ops:-0}" -ge "${durable:-1}" ] || { verdict=FAIL; echo "FAIL $display $state: $durable strokes durable, $ops operations in the scene written at exit"; }
  fi
  [ "$verdict" = ok ] || fail=1
  printf '%-4s %-8s %-9s exit %d in %4d ms\n' "$verdict" "$display" "$state" "$rc" "$ms"
}

for display in "${backends[@]}"; do
  for state in starting attract visitor staff exporting; do
    one "$display" "$state"
  done
done
[ "$fail" -eq 0 ] && echo "kiosk_sigterm: every case exited 0 within $limit s" || echo "kiosk_sigterm: FAILED"
exit "$fail"

#!/usr/bin/env bash
# Crash test of the session journal: the kiosk replays a visitor's recording headless at its own pace
# and is killed with SIGKILL at a random moment; the next start must bring back every stroke the
# killed kiosk had reported durable ("journal: stroke N durable"), and every start must succeed.
# Then the same with the store torn after the kill (the WAL's tail cut, a byte flipped, the file
# replaced by garbage): the kiosk must start, say what it did, and keep running.
#   kiosk_crash.sh BIN_DIR SOURCE_DIR        EMBOSS_CRASH_RUNS=50 for the long mode (default 4)
set -u
bin="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
kiosk="$bin/emboss-kiosk"
[ -x "$kiosk" ] || { echo "skip: no emboss-kiosk"; exit 77; }
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
runs=${EMBOSS_CRASH_RUNS:-4}
seed=${EMBOSS_CRASH_SEED:-$$}
RANDOM=$seed
fail=0
demo="$src/tests/app/data/visitor-demo.events"
common=(--display=headless --size 160x100 --threads 1 --sessions-dir "$tmp/sessions" --pieces "$src/firmware-app/pieces" --log-level=debug)

# The strokes the last start restored (0 when it restored nothing).
restored() { sed -n 's/.*session: restored session [0-9]*: \([0-9]*\) strokes.*/\1/p' "$1" | tail -1; }
# The highest stroke a run reported durable in its (restored or new) session.
durable() { sed -n 's/.*journal: stroke \([0-9]*\) durable.*/\1/p' "$1" | sort -n | tail -1; }

# One run: replay, kill at a random moment between 1.5 and 12 s, report what was durable.
run_and_kill() {
  local log=$1 ms=$((1500 + RANDOM % 10500))
  "$kiosk" "${common[@]}" --tablet="evemu:$demo" >"$log.out" 2>"$log" &
  local pid=$!
  sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
  if ! kill -0 "$pid" 2>/dev/null; then
    wait "$pid"; echo "FAIL the kiosk had stopped by itself before the kill (exit $?)"; tail -5 "$log"; fail=1; return
  fi
  kill -KILL "$pid"; wait "$pid" 2>/dev/null
  echo "$ms"
}

# A start that must succeed and bring back at least $1 strokes; it ends cleanly (SIGTERM's path).
check_restart() {
  local want=$1 log=$2 label=$3
  "$kiosk" "${common[@]}" --tablet=none --run-for 1.5 --session-out "$log.json" >"$log.out" 2>"$log"
  local rc=$? got
  got=$(restored "$log"); got=${got:-0}
  if [ "$rc" -ne 0 ]; then echo "FAIL $label: the restart exited $rc"; tail -5 "$log"; fail=1; return; fi
  if [ "$got" -lt "$want" ]; then
    echo "FAIL $label: $want strokes were reported durable, $got came back"; grep -E 'journal|session' "$log" | tail -5; fail=1; return
  fi
  echo "$got"
}

kills=0; checked=0; lost=0
for i in $(seq "$runs"); do
  ms=$(run_and_kill "$tmp/run$i.err")
  case "$ms" in FAIL*) echo "$ms"; continue ;; esac
  want=$(durable "$tmp/run$i.err"); want=${want:-0}
  kills=$((kills + 1))
  got=$(check_restart "$want" "$tmp/check$i.err" "run $i (killed at $ms ms)")
  case "$got" in FAIL*) echo "$got"; lost=$((lost + 1)); continue ;; esac
  checked=$((checked + want))
  echo "ok   run $i: killed at $ms ms with $want strokes durable; $got restored"
done

# Torn stores: a session in the journal, killed, then damaged in three ways.
for damage in tail flip garbage; do
  rm -rf "$tmp/sessions"
  run_and_kill "$tmp/torn-$damage.err" >/dev/null
  db="$tmp/sessions/sessions.db"
  case "$damage" in
    tail)  # the WAL (where the last commits are) cut at a random point
      if [ -s "$db-wal" ]; then size=$(stat -c %s "$db-wal"); truncate -s $((RANDOM * 32768 % size)) "$db-wal"; fi ;;
    flip)  # one byte flipped in the middle of the database (after a checkpoint)
      sqlite3 "$db" 'PRAGMA wal_checkpoint(TRUNCATE)' >/dev/null 2>&1 || true
      size=$(stat -c %s "$db"); off=$((size / 2 + RANDOM % (size / 2)))
      printf '\xa5' | dd of="$db" bs=1 seek="$off" conv=notrunc status=none ;;
    garbage)
      rm -f "$db-wal" "$db-shm"; head -c 20000 /dev/urandom >"$db" ;;
  esac
  "$kiosk" "${common[@]}" --tablet=none --run-for 1.5 --session-out "$tmp/torn-$damage.json" >"$tmp/torn-$damage.out" 2>"$tmp/torn-$damage.check"
  rc=$?
  if [ "$rc" -ne 0 ]; then echo "FAIL torn ($damage): the kiosk exited $rc"; tail -5 "$tmp/torn-$damage.check"; fail=1; continue; fi
  if [ "$damage" = garbage ]; then
    grep -q 'journal: .*damaged.*moved aside' "$tmp/torn-$damage.check" || { echo "FAIL torn (garbage): not reported and moved aside"; cat "$tmp/torn-$damage.check"; fail=1; }
    ls "$tmp/sessions"/sessions.db.corrupt-* >/dev/null 2>&1 || { echo "FAIL torn (garbage): the damaged store was not kept aside"; fail=1; }
  fi
  # The next start after a damaged one works on a sound store.
  "$kiosk" "${common[@]}" --tablet=none --run-for 0.5 >/dev/null 2>"$tmp/torn-$damage.again" || { echo "FAIL torn ($damage): the start after it failed"; fail=1; }
  if grep -q 'damaged' "$tmp/torn-$damage.again"; then echo "FAIL torn ($damage): still damaged on the next start"; fail=1; fi
  echo "ok   torn store ($damage): started, $(grep -cE 'journal: .*(damaged|dropped)|session: .*dropped' "$tmp/torn-$damage.check") damage reports, $(restored "$tmp/torn-$damage.check" || true) strokes restored"
done

echo "crash test: $kills kills, $checked durable strokes checked, $lost runs lost strokes (seed $seed)"
[ "$lost" -eq 0 ] || fail=1
exit $fail

# Shared by the HIL shell tests (sourced): checks that print "ok - ..." or "FAIL - ..." with the
# seconds since the test started, a failure count, and a wall-clock wait.
tmp=$(mktemp -d)
fail=0
t0=$(date +%s)
at() { echo "$(($(date +%s) - t0)) s"; }
ok() { echo "ok - $* [$(at)]"; }
bad() { echo "FAIL - $* [$(at)]"; fail=$((fail + 1)); }
wait_for() {  # wait_for SECONDS COMMAND...: true once COMMAND succeeds within SECONDS of wall time
  deadline=$(($(date +%s) + $1)); shift
  while ! "$@"; do
    [ "$(date +%s)" -ge "$deadline" ] && return 1
    sleep 0.2
  done
}
stacks() {  # stacks PID: where a process that does not end is (gdb's backtraces, else the kernel's)
  echo "--- where pid $1 is:"
  if command -v gdb >/dev/null 2>&1; then
    gdb -q -batch -p "$1" -ex 'thread apply all bt 30' 2>&1 | grep -v -e '^\[New LWP' -e '^Using host' | head -150
  fi
  for t in /proc/"$1"/task/*; do
    echo "thread ${t##*/} ($(cat "$t/comm" 2>/dev/null)): $(cat "$t/wchan" 2>/dev/null)"
    cat "$t/stack" 2>/dev/null | head -12
  done
}

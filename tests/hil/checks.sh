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

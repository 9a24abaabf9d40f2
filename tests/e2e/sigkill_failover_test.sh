#!/usr/bin/env bash
# e2e.fault_sigkill_failover: two koma_server backends on loopback behind the client's own
# balancing (koma_load --server a,b: round_robin over the SERVING servers, UNAVAILABLE retried,
# the koma client's service config); about 1 s into 4 s of load (concurrency 8, samples/
# pitch.bvh), once both have answered calls, backend a is killed with SIGKILL: no drain, its
# calls in flight cut. Checks: every call succeeds (a cut call fails UNAVAILABLE and its retry
# goes to b), and b answered calls after a died. Prints the calls per backend.
#   sigkill_failover_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_server_as
set -euo pipefail
server_bin=$1 load_bin=$2 pitch=$3
# shellcheck source=fault_lib.sh
. "$(dirname "$0")/fault_lib.sh"

start_server_as a "$server_bin" --log_format=json
start_server_as b "$server_bin" --log_format=json

"$load_bin" --rpc skeletal --input "$pitch" --concurrency 8 --duration 4 --count 100000 \
  --max-duration 30 --deadline 10 --server "$target_a,$target_b" --json "$work/load.json" \
  --quiet >"$work/load.out" 2>&1 &
load_pid=$!
pids_to_kill+=("$load_pid")
sleep 1
wait_until 5 both_answered 5 || true
running "$load_pid" || fail "koma_load ended before the SIGKILL: $(cat "$work/load.out")"
a_before=$(answered_ok "$work/a.log")
b_before=$(answered_ok "$work/b.log")
kill_server_as a
code=0
reap "$load_pid" || code=$?
[ "$code" = 0 ] || fail "koma_load exited $code: $(cat "$work/load.out")"
b_after=$(($(answered_ok "$work/b.log") - b_before))

count=$(report "$work/load.json" count)
ok=$(report "$work/load.json" ok)
echo "$count calls, $ok OK, errors $(report "$work/load.json" errors); a answered $a_before" \
  "before its SIGKILL, b $b_before before and $b_after after"
[ "$count" -gt 0 ] && [ "$ok" = "$count" ] || fail "calls failed: $(report "$work/load.json" errors)"
[ "$a_before" -ge 1 ] || fail "backend a answered no call before its SIGKILL"
[ "$b_after" -ge 1 ] || fail "backend b answered no call after a's SIGKILL"
stop_server_as b
echo "PASS"

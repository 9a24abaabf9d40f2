#!/usr/bin/env bash
# e2e.fault_sigkill_failover: two koma_server backends on loopback behind the client's own
# balancing (koma_load --server a,b: round_robin over the SERVING servers, UNAVAILABLE retried,
# the koma client's service config); about 1 s into 4 s of load (concurrency 8, samples/
# pitch.bvh), once both have answered calls, backend a is killed with SIGKILL: no drain, its
# calls in flight cut. Checks: every call succeeds (a cut call fails UNAVAILABLE and its retry
# goes to b), and b answered calls after a died. Prints the calls per backend.
#   sigkill_failover_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
server_bin=$1
load_bin=$2
pitch=$3
# shellcheck source=lib.sh
. "$here/lib.sh"
# shellcheck source=fault_lib.sh
. "$here/fault_lib.sh"

start_server "$server_bin" --log_format=json
a_pid=$server_pid a_target=$target
mv "$work/server.log" "$work/a.log"
# lib.sh's cleanup kills $server_pid only: a is killed here or by this trap.
trap 'kill -KILL "$a_pid" 2>/dev/null || true; cleanup' EXIT
start_server "$server_bin" --log_format=json
b_target=$target

answered() { grep -c '"code":"OK".*"method":"RetimeSkeletal"' "$1" || true; }

"$load_bin" --rpc skeletal --input "$pitch" --concurrency 8 --duration 4 --count 100000 \
  --max-duration 30 --deadline 10 --server "$a_target,$b_target" --json "$work/load.json" \
  --quiet >"$work/load.out" 2>&1 &
load_pid=$!
sleep 1
for _ in $(seq 50); do
  if [ "$(answered "$work/a.log")" -ge 5 ] && [ "$(answered "$work/server.log")" -ge 5 ]; then break; fi
  sleep 0.1
done
kill -0 "$load_pid" 2>/dev/null || fail "koma_load ended before the SIGKILL: $(cat "$work/load.out")"
a_before=$(answered "$work/a.log")
b_before=$(answered "$work/server.log")
kill -KILL "$a_pid"
wait "$a_pid" 2>/dev/null || true
code=0
wait "$load_pid" || code=$?
[ "$code" = 0 ] || fail "koma_load exited $code: $(cat "$work/load.out")"
b_after=$(($(answered "$work/server.log") - b_before))

count=$(report "$work/load.json" count)
ok=$(report "$work/load.json" ok)
echo "$count calls, $ok OK, errors $(report "$work/load.json" errors); a answered $a_before" \
  "before its SIGKILL, b $b_before before and $b_after after"
[ "$count" -gt 0 ] && [ "$ok" = "$count" ] || fail "calls failed: $(report "$work/load.json" errors)"
[ "$a_before" -ge 1 ] || fail "backend a answered no call before its SIGKILL"
[ "$b_after" -ge 1 ] || fail "backend b answered no call after a's SIGKILL"
stop_server
echo "PASS"

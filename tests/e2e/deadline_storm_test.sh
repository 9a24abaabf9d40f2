#!/usr/bin/env bash
# e2e.fault_deadline_storm: 1,000 RetimeSkeletal calls of 5 MB (6,500 frames x 96 channels)
# with 1 ms deadlines, 16 at a time, against koma_server with --max_memory_mb=512. Most expire
# mid-upload or mid-run. Checks: every call ends OK, DEADLINE_EXCEEDED or RESOURCE_EXHAUSTED;
# afterwards no call is left in flight and the memory budget holds nothing (no reservation
# leaked), the server's RSS returns to within 24 MiB of its level after a warm-up of the same
# calls with a long deadline, and a call still succeeds. Prints the figures.
#   deadline_storm_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
server_bin=$1
load_bin=$2
pitch=$3
# shellcheck source=lib.sh
. "$here/lib.sh"
# shellcheck source=fault_lib.sh
. "$here/fault_lib.sh"

calls() {  # calls COUNT DEADLINE_S JSON
  "$load_bin" --rpc skeletal --frames 6500 --joints 31 --concurrency 16 --channels 4 \
    --count "$1" --deadline "$2" --max-duration 120 --server "$target" --json "$3" --quiet \
    >"$work/load.out" 2>&1 || fail "koma_load: $(cat "$work/load.out")"
}

start_server "$server_bin" --max_memory_mb=512 --log_level=warn --idle_trim_ms=500 \
  --metrics_address=127.0.0.1:0 --metrics_port_file="$work/metrics_port"
find_metrics
calls 64 60 "$work/warmup.json"
[ "$(report "$work/warmup.json" ok)" = 64 ] || fail "warm-up: $(report "$work/warmup.json" errors)"
sleep 2  # the idle trim gives the warm-up's heap back
rest_mb=$(rss_mib "$server_pid")

calls 1000 0.001 "$work/storm.json"
count=$(report "$work/storm.json" count)
ok=$(report "$work/storm.json" ok)
expired=$(report "$work/storm.json" errors.DEADLINE_EXCEEDED)
exhausted=$(report "$work/storm.json" errors.RESOURCE_EXHAUSTED)
echo "storm: $count calls with 1 ms deadlines: $ok OK, $expired DEADLINE_EXCEEDED," \
  "$exhausted RESOURCE_EXHAUSTED; server peak RSS $(peak_rss_mib "$server_pid") MiB"
[ "$count" = 1000 ] || fail "koma_load made $count calls, want 1000"
[ "$((ok + expired + exhausted))" = 1000 ] ||
  fail "calls ended with other codes: $(report "$work/storm.json" errors)"

# Calls the server still runs finish (or are cancelled) shortly after their clients gave up.
for _ in $(seq 100); do
  [ "$(metric koma_requests_in_flight)" = 0.0 ] && break
  sleep 0.1
done
[ "$(metric koma_requests_in_flight)" = 0.0 ] || fail "calls still in flight 10 s after the storm"
[ "$(metric koma_memory_budget_in_use_bytes)" = 0.0 ] ||
  fail "the memory budget still holds $(metric koma_memory_budget_in_use_bytes) bytes"
wait_rss_at_most "$server_pid" $((rest_mb + 24)) 15
echo "server RSS after the warm-up ${rest_mb} MiB, after the storm $(rss_mib "$server_pid") MiB"
"$load_bin" --rpc skeletal --input "$pitch" --count 3 --server "$target" --fail-on-error --quiet \
  >"$work/after.out" 2>&1 || fail "a call after the storm failed: $(cat "$work/after.out")"
stop_server
echo "PASS"

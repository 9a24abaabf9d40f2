#!/usr/bin/env bash
# e2e.fault_deadline_storm: 1,000 RetimeSkeletal calls of 5 MB (6,500 frames x 96 channels)
# with 1 ms deadlines, 16 at a time, against koma_server with --max_memory_mb=512. Most expire
# mid-upload or mid-run. Checks: every call ends OK, DEADLINE_EXCEEDED or RESOURCE_EXHAUSTED;
# afterwards no call is left in flight and the memory budget holds nothing (no reservation
# leaked), the server's RSS returns to within 24 MiB of its level after a warm-up of the same
# calls with a long deadline, and a call still succeeds. Prints the figures.
#   deadline_storm_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH
set -euo pipefail
server_bin=$1 load_bin=$2 pitch=$3
# shellcheck source=fault_lib.sh
. "$(dirname "$0")/fault_lib.sh"

calls() {  # calls COUNT DEADLINE_S JSON
  "$load_bin" --rpc skeletal --frames 6500 --joints 31 --concurrency 16 --channels 4 \
    --count "$1" --deadline "$2" --max-duration 120 --server "$target" --json "$3" --quiet \
    >"$work/load.out" 2>&1 || fail "koma_load: $(cat "$work/load.out")"
}

start_server "$server_bin" --max_memory_mb=512 --log_level=warn --idle_trim_ms=500 \
  "${with_metrics[@]}"
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
check_released "after the storm"
wait_rss_at_most "$server_pid" $((rest_mb + 24)) 15
echo "server RSS after the warm-up ${rest_mb} MiB, after the storm $(rss_mib "$server_pid") MiB"
check_still_serves "after the storm" "$load_bin" "$pitch"
stop_server
echo "PASS"

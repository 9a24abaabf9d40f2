#!/usr/bin/env bash
# e2e.fault_disconnect: clients that vanish mid-upload. Five times, koma_load starts 16
# concurrent 50 MB RetimeSkeletal calls (65,000 frames x 96 channels) over 4 connections and
# is killed with SIGKILL once the server's RSS has grown by 64 MiB, that is while the
# requests are being received (its sockets close with no RST_STREAM or GOAWAY first). Checks: the server stays up, no call is left in
# flight, the memory budget holds nothing, RSS returns to within 24 MiB of rest, and a call
# still succeeds. Prints the figures.
#   disconnect_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH
set -euo pipefail
server_bin=$1 load_bin=$2 pitch=$3
# shellcheck source=fault_lib.sh
. "$(dirname "$0")/fault_lib.sh"

start_server "$server_bin" --max_memory_mb=1024 --log_format=json --idle_trim_ms=500 \
  "${with_metrics[@]}"
check_still_serves "before the disconnects" "$load_bin" "$pitch"
rest_mb=$(rss_mib "$server_pid")

rounds=()
for round in 1 2 3 4 5; do
  sleep 1
  rounds+=("$(rss_mib "$server_pid")")
  "$load_bin" --rpc skeletal --frames 65000 --joints 31 --concurrency 16 --channels 4 \
    --count 16 --deadline 60 --max-duration 60 --server "$target" --quiet \
    >"$work/load.out" 2>&1 &
  load_pid=$!
  poll_interval=0.02 wait_until 10 rss_above "$server_pid" $((rest_mb + 64)) ||
    fail "round $round: the server's RSS never grew: no upload reached it in 10 s"
  kill -KILL "$load_pid" 2>/dev/null || true
  wait "$load_pid" 2>/dev/null || true
  kill -0 "$server_pid" 2>/dev/null || fail "the server died in round $round"
done
sleep 1
rounds+=("$(rss_mib "$server_pid")")
echo "server RSS before each round and after the last: ${rounds[*]} MiB"
[ "${rounds[5]}" -le $((rounds[2] + 24)) ] ||
  fail "RSS grew from ${rounds[2]} MiB (after round 2) to ${rounds[5]} MiB (after round 5)"

check_released "after the last kill"
"$load_bin" --rpc skeletal --frames 6500 --joints 31 --count 4 --server "$target" \
  --fail-on-error --quiet >"$work/after.out" 2>&1 ||
  fail "5 MB calls after the disconnects failed: $(cat "$work/after.out")"
wait_rss_at_most "$server_pid" $((rest_mb + 24)) 15
ran=$(grep -c '"bytes_in":49922386' "$work/server.log" || true)
echo "5 rounds of 16 x 50 MB uploads cut by SIGKILL: $ran calls reached the service" \
  "(the rest died mid-upload); server peak RSS $(peak_rss_mib "$server_pid") MiB," \
  "RSS at rest ${rest_mb} MiB, after $(rss_mib "$server_pid") MiB"
check_still_serves "after the disconnects" "$load_bin" "$pitch"
stop_server
echo "PASS"

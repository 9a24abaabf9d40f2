#!/usr/bin/env bash
# End to end: koma_server refuses every setting out of range at start, from the command line
# or from KOMA_<FLAG> in the environment: exit 1, the flag and the value named, nothing bound
# (each attempt is bounded by a 10 s timeout). Then the lowest accepted values do start.
# Usage: server_flags_e2e_test.sh KOMA_SERVER
set -euo pipefail
server_bin=$1

source "$(dirname "$0")/lib.sh"

check_refused '--worker_threads: -1 must be >= 0' "$server_bin" --worker_threads=-1
check_refused '--max_queued: -5 must be >= 0' "$server_bin" --max_queued=-5
check_refused '--max_values: 0 must be >= 1' "$server_bin" --max_values=0
check_refused '--max_joints: -3 must be >= 1' "$server_bin" --max_joints=-3
check_refused '--max_message_bytes: 0 is below 1024' "$server_bin" --max_message_bytes=0
check_refused '--inline_max_bytes: -1 must be >= 0' "$server_bin" --inline_max_bytes=-1
check_refused '--idle_trim_ms: -1 must be >= 0' "$server_bin" --idle_trim_ms=-1
check_refused '--threads_per_call: -2 must be >= 0 (0 = one per core)' "$server_bin" \
  --threads_per_call=-2
check_refused '--huge_page_cache_mb: -1 must be >= 0' "$server_bin" --huge_page_cache_mb=-1
check_refused '--shutdown_delay_ms: -1 must be >= 0' "$server_bin" --shutdown_delay_ms=-1
check_refused '--shutdown_grace_ms: -1 must be >= 0' "$server_bin" --shutdown_grace_ms=-1
check_refused '--log_level: "loud"' "$server_bin" --log_level=loud
check_refused "--tls_cert: cannot read $work/none.pem" "$server_bin" --tls_cert="$work/none.pem"
check_refused "Illegal value 'many' specified for flag 'max_queued'" "$server_bin" \
  --max_queued=many

# The same checks for the environment (how the container is configured).
KOMA_MAX_JOINTS=-3 check_refused '--max_joints: -3 must be >= 1' "$server_bin"
KOMA_SHUTDOWN_GRACE_MS=-1 check_refused '--shutdown_grace_ms: -1 must be >= 0' "$server_bin"
KOMA_MAX_VALUES=lots check_refused 'KOMA_MAX_VALUES="lots"' "$server_bin"

# The lowest values accepted start a server (it writes its port) that stops cleanly.
start_server "$server_bin" --log_level=warn --worker_threads=0 --max_queued=0 --max_values=1 \
  --max_joints=1 --inline_max_bytes=0 --idle_trim_ms=0 --threads_per_call=0 \
  --huge_page_cache_mb=0 --shutdown_delay_ms=0 --shutdown_grace_ms=0 --max_message_bytes=1024
stop_server
echo "PASS: server flags"

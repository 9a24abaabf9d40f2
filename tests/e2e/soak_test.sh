#!/usr/bin/env bash
# Soak: koma_server under a steady mix of all three RPCs (RetimeSkeletal on samples/pitch.bvh,
# RetimeCurves on arm_head.motion3.json, LipBlink on talk_blink.motion3.json; two calls
# outstanding each) for SECONDS, its RSS sampled every second. Checks: every call succeeds;
# RSS stays flat: the largest sample of the last third is within max(16 MiB, 10 %) of the
# largest of the middle third (the first third is warm-up); afterwards the memory budget
# holds nothing. Prints calls, samples and the two maxima.
#   soak_test.sh KOMA_SERVER KOMA_LOAD PITCH_BVH ARM_HEAD_MOTION3 TALK_BLINK_MOTION3 SECONDS
# ctest runs it for 30 s (e2e.soak_smoke); scripts/soak.sh runs it for minutes.
set -euo pipefail
server_bin=$1 load_bin=$2 pitch=$3 arm_head=$4 talk_blink=$5 seconds=$6
# shellcheck source=fault_lib.sh
. "$(dirname "$0")/fault_lib.sh"

start_server "$server_bin" --max_memory_mb=512 --log_level=warn "${with_metrics[@]}"
loads=()
load() {  # load NAME RPC INPUT
  "$load_bin" --rpc "$2" --input "$3" --concurrency 2 --duration "$seconds" --count 100000000 \
    --max-duration $((seconds + 60)) --server "$target" --json "$work/$1.json" --quiet \
    >"$work/$1.out" 2>&1 &
  loads+=($!)
}
load skeletal skeletal "$pitch"
load curves curves "$arm_head"
load lipblink lipblink "$talk_blink"

: >"$work/rss.txt"
for _ in $(seq "$seconds"); do
  sleep 1
  rss_mib "$server_pid" >>"$work/rss.txt"
  echo >>"$work/rss.txt"
done
for pid in "${loads[@]}"; do
  wait "$pid" || fail "koma_load exited non-zero: $(cat "$work"/*.out)"
done

for name in skeletal curves lipblink; do
  count=$(report "$work/$name.json" count)
  ok=$(report "$work/$name.json" ok)
  echo "$name: $count calls, $ok OK"
  [ "$count" -gt 0 ] && [ "$ok" = "$count" ] ||
    fail "$name: calls failed: $(report "$work/$name.json" errors)"
done
/usr/bin/python3 - "$work/rss.txt" <<'PY' || fail "RSS did not stay flat"
import sys
samples = [int(line) for line in open(sys.argv[1]) if line.strip()]
third = len(samples) // 3
middle, last = max(samples[third:2 * third]), max(samples[2 * third:])
allowed = middle + max(16, middle // 10)
print("RSS samples (MiB, one per second): %d, first %d, largest of the middle third %d, "
      "of the last third %d (allowed %d)" % (len(samples), samples[0], middle, last, allowed))
sys.exit(0 if last <= allowed else 1)
PY
check_released "after the soak"
stop_server
echo "PASS"

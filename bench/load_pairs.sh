#!/usr/bin/env bash
# Alternated pairs over loopback: koma_load against one server, then the other, ROUNDS times
# (the order flips every round), with a fresh server process for every run. On a shared,
# noisy host two runs seconds apart see about the same host, so their ratio is steadier than
# a matrix cell's; the median over the rounds is what docs/benchmarks.md quotes as "pairs".
#   bench/load_pairs.sh --rpc skeletal --frames 129 --joints 31 --concurrency 16 --channels 4
#   ROUNDS=6 DURATION=5 WARMUP=1 bench/load_pairs.sh --rpc skeletal --frames 129 --joints 31 \
#       --form positions --concurrency 16 --channels 4
#   A="/tmp/old/build/server/koma_server" bench/load_pairs.sh ...   (an old build against echo)
#   B="build-release/server/koma_server" bench/load_pairs.sh ...    (koma against koma)
# The arguments go to koma_load as they are (not --target, --duration, --warmup, --json).
# Servers A (default koma_server --log_level=warn) and B (default koma_echo_server) listen on
# 127.0.0.1 port 0 and are stopped after each run. Prints one line per round and the medians:
# RPS A / B (closed loop: the throughput ratio) and p50 B / A (the latency ratio).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-release}
rounds=${ROUNDS:-6}
duration=${DURATION:-5}  # measured seconds per run
warmup=${WARMUP:-1}      # seconds per run left out of the statistics
server_a=${A:-$build/server/koma_server --log_level=warn}
server_b=${B:-$build/bench/koma_echo_server}
load=$build/bench/koma_load
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($server_pid, $target), stop_server

# run NAME SERVER_COMMAND -- LOAD ARGS: one server, one koma_load run; writes "rps p50" to
# $work/NAME.result. Runs in this shell (not in $(...)), so the EXIT trap knows the server.
run() {
  local name=$1 command=$2
  shift 3
  # shellcheck disable=SC2086  # the server command is a word list (binary and flags)
  start_server $command
  "$load" --target "$target" --duration "$duration" --warmup "$warmup" \
    --deadline 60 --quiet --fail-on-error --json "$work/$name.json" "$@"
  stop_server
  python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))
print("%.1f %.3f" % (r["rps"], r["latency_ms"]["p50"]))' "$work/$name.json" >"$work/$name.result"
}

echo "A: $server_a"
echo "B: $server_b"
: >"$work/ratios"
for round in $(seq "$rounds"); do
  if ((round % 2)); then order="a b"; else order="b a"; fi
  for side in $order; do
    if [ "$side" = a ]; then run a "$server_a" -- "$@"; else run b "$server_b" -- "$@"; fi
  done
  read -r rps_a p50_a <"$work/a.result"
  read -r rps_b p50_b <"$work/b.result"
  python3 - "$round" "$rps_a" "$p50_a" "$rps_b" "$p50_b" "$work/ratios" <<'PY'
import sys
round_, rps_a, p50_a, rps_b, p50_b, path = sys.argv[1:]
rps_ratio = float(rps_a) / float(rps_b)
p50_ratio = float(p50_a) / float(p50_b)
open(path, "a").write("%f %f\n" % (rps_ratio, p50_ratio))
print("round %s: A %s RPS, p50 %s ms | B %s RPS, p50 %s ms | RPS A/B %.3f | p50 A/B %.3f"
      % (round_, rps_a, p50_a, rps_b, p50_b, rps_ratio, p50_ratio))
PY
done
python3 - "$work/ratios" <<'PY'
import statistics, sys
rows = [tuple(map(float, line.split())) for line in open(sys.argv[1])]
print("median over %d rounds: RPS A/B %.3f, p50 A/B %.3f"
      % (len(rows), statistics.median(r[0] for r in rows), statistics.median(r[1] for r in rows)))
PY

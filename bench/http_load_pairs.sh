#!/usr/bin/env bash
# The same call over gRPC (koma_load) and over the HTTP port's Connect API in binary and in
# JSON (koma_http_load), against one koma_server, closed loop at the same concurrency,
# alternated ROUNDS times (the order rotates every round) so each is measured on about the
# same host; prints each run and the medians of calls/s and p50 (docs/benchmarks.md).
#   bench/http_load_pairs.sh --rpc skeletal --frames 129 --joints 31 --concurrency 4
#   ROUNDS=5 DURATION=4 WARMUP=1 BUILD_DIR=build bench/http_load_pairs.sh --rpc curves ...
# The arguments go to both tools (--rpc, --input, --frames, --joints, --curves, --concurrency).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-release}
rounds=${ROUNDS:-5}
duration=${DURATION:-4}  # measured seconds per run
warmup=${WARMUP:-1}      # seconds per run left out of the statistics
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($target), stop_server

start_server "$build/server/koma_server" --log_level=warn --http_port=0 \
  --http_port_file="$work/http.port"
url="http://127.0.0.1:$(cat "$work/http.port")"
: >"$work/runs"
run() {  # run NAME: one measured run, "NAME rps p50" appended to $work/runs
  case $1 in
    grpc)
      "$build/bench/koma_load" --target "$target" --duration "$duration" --warmup "$warmup" \
        --deadline 60 --quiet --fail-on-error --json "$work/grpc.json" "${args[@]}"
      python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))
print("grpc %.1f %.3f" % (r["rps"], r["latency_ms"]["p50"]))' "$work/grpc.json" >>"$work/runs" ;;
    http_proto | http_json)
      local flag=()
      [ "$1" = http_json ] && flag=(--json-body)
      "$build/bench/koma_http_load" --url "$url" --duration "$duration" --warmup "$warmup" \
        "${flag[@]}" "${args[@]}" >"$work/http.json"
      python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))
print("%s %.1f %.3f" % (sys.argv[2], r["rps"], r["p50_ms"]))' "$work/http.json" "$1" \
        >>"$work/runs" ;;
  esac
  tail -1 "$work/runs"
}
args=("$@")
orders=("grpc http_proto http_json" "http_proto http_json grpc" "http_json grpc http_proto")
for round in $(seq "$rounds"); do
  for name in ${orders[$(((round - 1) % 3))]}; do run "$name"; done
done
stop_server
python3 - "$work/runs" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    name, rps, p50 = line.split()
    runs.setdefault(name, []).append((float(rps), float(p50)))
grpc = statistics.median(r for r, _ in runs['grpc'])
print('%-11s %9s %9s %8s' % ('transport', 'calls/s', 'p50 ms', 'vs gRPC'))
for name in ('grpc', 'http_proto', 'http_json'):
    rps = statistics.median(r for r, _ in runs[name])
    p50 = statistics.median(p for _, p in runs[name])
    print('%-11s %9.0f %9.3f %7.2fx' % (name, rps, p50, rps / grpc))
PY

#!/usr/bin/env bash
# Server API matrix over loopback (issue 5): koma_api_server under each gRPC server API and
# thread count, the same koma_load runs against each, side by side. Prints a markdown table
# (summed up in docs/benchmarks.md, "Findings") with each cell's RPS against
# production's model (callback_pool, 2 workers = koma_server's default on 2 cores).
#   bench/api_matrix.sh                  build Release into build-api, one round
#   RUNS=2 BUILD_DIR=build-x SKIP_BUILD=1 DURATION=2 bench/api_matrix.sh
#   CONFIGS="callback_pool:2 async:2" bench/api_matrix.sh
# Every server runs for the whole round and cells go through all of them one after another,
# so each ratio compares runs seconds apart (the machine is shared and noisy). Each round
# restarts the servers.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-api}
duration=${DURATION:-3}  # measured seconds per run
warmup=${WARMUP:-0.5}    # seconds per run left out of the statistics
runs=${RUNS:-1}          # rounds of the whole matrix; the table shows each and the median
concurrencies=${CONCURRENCIES:-"1 4 8"}
# api:worker_threads. sync:0 is gRPC's default (no thread limit); callback_pool:2 is
# production and the reference of the ratio column.
configs=${CONFIGS:-"sync:0 sync:2 sync:4 callback_inline:0 callback_pool:1 callback_pool:2 callback_pool:4 async:1 async:2 async:4"}
reference=callback_pool:2

if [ -z "${SKIP_BUILD:-}" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target koma_api_server koma_load >/dev/null
fi
load=$build/bench/koma_load
server=$build/bench/koma_api_server
work=$(mktemp -d)
declare -A pid port
cleanup() {
  for p in "${pid[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

start_all() {
  for config in $configs; do
    local name=${config/:/_}
    rm -f "$work/$name.port"
    "$server" --api="${config%%:*}" --worker_threads="${config##*:}" --address=127.0.0.1:0 \
      --port_file="$work/$name.port" 2>>"$work/server.log" &
    pid[$config]=$!
  done
  for config in $configs; do
    local name=${config/:/_}
    for _ in $(seq 100); do [ -s "$work/$name.port" ] && break; sleep 0.1; done
    [ -s "$work/$name.port" ] || { echo "$config did not start" >&2; cat "$work/server.log" >&2; exit 1; }
    port[$config]=$(cat "$work/$name.port")
  done
}

stop_all() {  # SIGTERM each; each must exit 0
  for config in $configs; do
    kill -TERM "${pid[$config]}"
    wait "${pid[$config]}" || { echo "$config exited $? after SIGTERM" >&2; exit 1; }
    unset "pid[$config]"
  done
}

# RPC label|koma_load flags
cases=(
  "skeletal positions 129x31|--rpc skeletal --form positions --frames 129 --joints 31"
  "skeletal channels 129x31|--rpc skeletal --form channels --frames 129 --joints 31"
  "curves 60x300|--rpc curves --curves 60 --frames 300"
  "lipblink 3x100k|--rpc lipblink --curves 3 --frames 100000"
)
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
for run in $(seq "$runs"); do
  start_all
  for case in "${cases[@]}"; do
    IFS='|' read -r label flags <<<"$case"
    for c in $concurrencies; do
      for config in $configs; do
        json=$work/r$run.json
        # shellcheck disable=SC2086  # $flags is a word list
        timeout 60 "$load" --target "127.0.0.1:${port[$config]}" --duration "$duration" \
          --warmup "$warmup" --deadline 20 --quiet --json "$json" $flags \
          --concurrency "$c" --channels "$(( c < 4 ? c : 4 ))"
        python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); r.update(run=int(sys.argv[2]), case=sys.argv[3], c=int(sys.argv[4]), config=sys.argv[5]); print(json.dumps(r))' \
          "$json" "$run" "$label" "$c" "$config" >>"$work/results.jsonl"
      done
    done
  done
  stop_all
  echo "round $run done; load average $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
[ -n "${RESULTS:-}" ] && cp "$work/results.jsonl" "$RESULTS"

python3 - "$work/results.jsonl" "$reference" <<'PY'
import collections, json, statistics, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
reference = sys.argv[2]
cells = collections.OrderedDict()  # (case, c, config) -> [row per run]
for r in rows:
    r["ok_rps"] = r["ok"] / r["measured_s"] if r["measured_s"] > 0 else 0.0
    cells.setdefault((r["case"], r["c"], r["config"]), []).append(r)
runs = max(r["run"] for r in rows)
def fmt(values, digits):
    text = " / ".join("%.*f" % (digits, v) for v in values)
    return text if len(values) == 1 else "%s (med %.*f)" % (text, digits, statistics.median(values))
print("| api | threads | RPC | concurrency | ok RPS | p50 ms | p99 ms | RPS / %s | errors |" % reference)
print("|---|--:|---|--:|--:|--:|--:|--:|---|")
for (case, c, config), rs in cells.items():
    ref = {r["run"]: r["ok_rps"] for r in cells[(case, c, reference)]}
    ratios = [r["ok_rps"] / ref[r["run"]] if ref.get(r["run"]) else 0.0 for r in rs]
    errors = sum(sum(r["errors"].values()) for r in rs)
    codes = ",".join(sorted({k for r in rs for k in r["errors"]}))
    api, threads = config.split(":")
    print("| %s | %s | %s | %d | %s | %s | %s | %s | %s |" % (
        api, threads if threads != "0" else "default", case, c,
        fmt([r["ok_rps"] for r in rs], 0), fmt([r["latency_ms"]["p50"] for r in rs], 2),
        fmt([r["latency_ms"]["p99"] for r in rs], 2), fmt(ratios, 2),
        "%d %s" % (errors, codes) if errors else ""))
# Per config over the whole matrix: geometric mean of the RPS ratio, and in how many cells
# (of all runs) it had more RPS and a p99 no worse than the reference.
print()
print("| api | threads | geomean RPS / %s | cells with more RPS and p99 <= reference | cells with errors |" % reference)
print("|---|--:|--:|--:|--:|")
for config in dict.fromkeys(k[2] for k in cells):
    ratios, better, with_errors, total = [], 0, 0, 0
    for (case, c, cfg), rs in cells.items():
        if cfg != config: continue
        for r in rs:
            ref = next(x for x in cells[(case, c, reference)] if x["run"] == r["run"])
            ratios.append(r["ok_rps"] / ref["ok_rps"])
            better += r["ok_rps"] > ref["ok_rps"] and r["latency_ms"]["p99"] <= ref["latency_ms"]["p99"]
            with_errors += bool(r["errors"])
            total += 1
    geo = statistics.geometric_mean(ratios) if all(x > 0 for x in ratios) else 0.0
    api, threads = config.split(":")
    print("| %s | %s | %.2f | %d / %d | %d |" % (api, threads if threads != "0" else "default",
                                                geo, better, total, with_errors))
PY

#!/usr/bin/env bash
# End-to-end load matrix over loopback: koma_server against koma_echo_server (the same
# service, computing nothing) for each RPC x payload size x concurrency, with koma_load.
# Prints a markdown table (docs/benchmarks.md, "End to end over loopback").
#   bench/load_matrix.sh                 build Release into build-release, run everything
#   BUILD_DIR=build-x SKIP_BUILD=1 DURATION=2 bench/load_matrix.sh
# Each cell restarts both servers, so "peak RSS" (VmHWM) is that cell's alone.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-release}
duration=${DURATION:-3}      # measured seconds per run
warmup=${WARMUP:-0.5}        # seconds per run left out of the statistics
concurrencies=${CONCURRENCIES:-"1 4 16"}

if [ -z "${SKIP_BUILD:-}" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target koma_server koma_echo_server koma_load >/dev/null
fi
load=$build/bench/koma_load
work=$(mktemp -d)
pid=""
cleanup() {
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid"; fi
  rm -rf "$work"
}
trap cleanup EXIT

# start BINARY [FLAGS...]: a server on a free loopback port; sets $pid and $port.
start() {
  rm -f "$work/port"
  "$@" --address=127.0.0.1:0 --port_file="$work/port" 2>>"$work/server.log" &
  pid=$!
  for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
  [ -s "$work/port" ] || { echo "server did not start: $*" >&2; cat "$work/server.log" >&2; exit 1; }
  port=$(cat "$work/port")
}

# stop: sets $rss to the server's peak RSS in MiB, then SIGTERM and wait (must exit 0).
stop() {
  rss=$(awk '/VmHWM/ { printf "%.0f", $2 / 1024 }' "/proc/$pid/status")
  kill -TERM "$pid"
  wait "$pid" || { echo "server exited $? after SIGTERM" >&2; exit 1; }
  pid=""
}

# measure NAME SERVER_BIN [SERVER FLAGS] -- LOAD ARGS: one run; prints "rps p50 p99 rss".
measure() {
  local name=$1 server_args=() rss=""
  shift
  while [ "$1" != "--" ]; do server_args+=("$1"); shift; done; shift
  start "${server_args[@]}"
  "$load" --target "127.0.0.1:$port" --duration "$run_s" --warmup "$warm_s" \
    --deadline 60 --quiet --json "$work/$name.json" "$@"
  stop
  python3 - "$work/$name.json" "$rss" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
errors = sum(r["errors"].values())
note = "" if errors == 0 else " (%d errors: %s)" % (errors, ",".join(r["errors"]))
print("%.1f|%.2f|%.2f|%s|%s" % (r["rps"], r["latency_ms"]["p50"], r["latency_ms"]["p99"],
                                sys.argv[2], note))
PY
}

echo "| RPC | size | concurrency | koma RPS | echo RPS | koma/echo | koma p50 / p99 (ms) | echo p50 / p99 (ms) | koma peak RSS (MiB) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
# RPC|size label|big (no warmup, twice the time: calls take up to seconds)|koma_load flags
cases=(
  "skeletal|129 frames x 31 joints|0|--rpc skeletal --frames 129 --joints 31"
  "skeletal|100k frames x 31 joints|1|--rpc skeletal --frames 100000 --joints 31"
  "curves|60 curves x 300 frames|0|--rpc curves --curves 60 --frames 300"
  "curves|500 curves x 10k frames|1|--rpc curves --curves 500 --frames 10000"
  "lipblink|3 curves x 100k frames|0|--rpc lipblink --curves 3 --frames 100000"
)
for case in "${cases[@]}"; do
  IFS='|' read -r rpc size big flags <<<"$case"
  if [ "$big" = 1 ]; then
    run_s=$(python3 -c "print(2 * $duration)"); warm_s=0
  else
    run_s=$duration; warm_s=$warmup
  fi
  for c in $concurrencies; do
    # shellcheck disable=SC2086  # $flags is a word list
    IFS='|' read -r k_rps k_p50 k_p99 k_rss k_note <<<"$(measure koma "$build/server/koma_server" --log_level=warn -- $flags --concurrency "$c" --channels "$(( c < 4 ? c : 4 ))")"
    # shellcheck disable=SC2086
    IFS='|' read -r e_rps e_p50 e_p99 _ e_note <<<"$(measure echo "$build/bench/koma_echo_server" -- $flags --concurrency "$c" --channels "$(( c < 4 ? c : 4 ))")"
    ratio=$(python3 -c "print('%.2f' % ($k_rps / $e_rps) if $e_rps > 0 else '-')")
    echo "| $rpc | $size | $c | $k_rps$k_note | $e_rps$e_note | $ratio | $k_p50 / $k_p99 | $e_p50 / $e_p99 | $k_rss |"
  done
done

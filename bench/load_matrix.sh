#!/usr/bin/env bash
# End-to-end load matrix over loopback: koma_server against koma_echo_server (the same
# service, computing nothing) for each RPC x payload size x concurrency, with koma_load.
# Prints a markdown table (docs/benchmarks.md, "End to end over loopback").
#   bench/load_matrix.sh                 build Release into build-release, run everything
#   BUILD_DIR=build-x SKIP_BUILD=1 DURATION=2 bench/load_matrix.sh
#   RUNS=6 ONLY="skeletal 100k.*channels" CONCURRENCIES=16 bench/load_matrix.sh   one cell, six
#     koma runs on one server (their peaks side by side tell a leak from run-to-run spread)
#   SMALL_ONLY=1 leaves out the large payloads, STRICT=1 fails on any failed call (the ctest
#   smoke, bench.matrix_smoke, runs with both)
# Each cell restarts both servers, so "peak RSS" (VmHWM) is that cell's alone; koma runs the
# cell RUNS times (default 2) on the same process and reports each run's own peak (growth
# check): VmHWM is reset before each run (/proc/PID/clear_refs), and each run after the first
# starts once the server has been idle for REST seconds (default 2, past koma_server's 1 s
# --idle_trim_ms), so every run starts from a server at rest. Memory a run leaked would still be held then; freed memory the
# heap kept from the first run would not.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build-release}
duration=${DURATION:-3}      # measured seconds per run
warmup=${WARMUP:-0.5}        # seconds per run left out of the statistics
concurrencies=${CONCURRENCIES:-"1 4 16"}
rest=${REST:-2}              # idle seconds before each of a cell's later koma runs
koma_runs=${RUNS:-2}         # koma runs per cell (the echo runs once)
only=${ONLY:-}               # a bash regex: only the rows whose "RPC size" matches

if [ -z "${SKIP_BUILD:-}" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j2 --target koma_server koma_echo_server koma_load >/dev/null
fi
load=$build/bench/koma_load
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($server_pid, $target), stop_server

# peak: the server's peak RSS since the last reset_peak (VmHWM), MiB.
peak() { awk '/VmHWM/ { printf "%.0f", $2 / 1024 }' "/proc/$server_pid/status"; }
# reset_peak: VmHWM back to the current RSS ("5" in clear_refs, Linux 4.0 and later).
reset_peak() {
  echo 5 >"/proc/$server_pid/clear_refs" || { echo "cannot reset the peak RSS" >&2; exit 1; }
}

# measure NAME RUNS SERVER_BIN [SERVER FLAGS] -- LOAD ARGS: RUNS identical runs on one server
# process; prints "rps|p50|p99|request bytes|response bytes|each run's peak RSS|errors"
# for the first run.
measure() {
  local name=$1 runs=$2 server_args=() peaks=""
  shift 2
  while [ "$1" != "--" ]; do server_args+=("$1"); shift; done; shift
  start_server "${server_args[@]}"
  for run in $(seq "$runs"); do
    if [ "$run" -gt 1 ]; then sleep "$rest"; fi
    reset_peak
    "$load" --target "$target" --duration "$run_s" --warmup "$warm_s" \
      --deadline 60 --quiet --json "$work/$name.$run.json" "$@"
    peaks="$peaks${peaks:+ / }$(peak)"
  done
  stop_server
  python3 - "$work/$name.1.json" "$peaks" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
errors = sum(r["errors"].values())
note = "" if errors == 0 else " (%d errors: %s)" % (errors, ",".join(r["errors"]))
print("%.1f|%.2f|%.2f|%d|%d|%s|%s" % (r["rps"], r["latency_ms"]["p50"], r["latency_ms"]["p99"],
                                      r["request_bytes"], r["response_bytes"]["max"],
                                      sys.argv[2], note))
PY
}

mib() { python3 -c "print('%.1f' % ($1 / 1048576))"; }

echo "| RPC | size | c | koma RPS | echo RPS | koma/echo | koma p50 / p99 ms | echo p50 / p99 ms | request MiB | response MiB koma / echo | koma peak RSS MiB, each run's own | RSS budget MiB |"
echo "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
# RPC|size label|big (no warmup, twice the time: calls take up to seconds)|koma_load flags
cases=(
  "skeletal|129 frames x 31 joints, channels|0|--rpc skeletal --frames 129 --joints 31"
  "skeletal|129 frames x 31 joints, positions|0|--rpc skeletal --frames 129 --joints 31 --form positions"
  "skeletal|100k frames x 31 joints, channels|1|--rpc skeletal --frames 100000 --joints 31"
  "skeletal|100k frames x 31 joints, positions|1|--rpc skeletal --frames 100000 --joints 31 --form positions"
  "curves|60 curves x 300 frames|0|--rpc curves --curves 60 --frames 300"
  "curves|500 curves x 10k frames|1|--rpc curves --curves 500 --frames 10000"
  "lipblink|3 curves x 100k frames|0|--rpc lipblink --curves 3 --frames 100000"
)
for case in "${cases[@]}"; do
  IFS='|' read -r rpc size big flags <<<"$case"
  if [ "$big" = 1 ] && [ -n "${SMALL_ONLY:-}" ]; then continue; fi
  if [ -n "$only" ] && ! [[ "$rpc $size" =~ $only ]]; then continue; fi
  if [ "$big" = 1 ]; then
    run_s=$(python3 -c "print(2 * $duration)"); warm_s=0
  else
    run_s=$duration; warm_s=$warmup
  fi
  for c in $concurrencies; do
    channels=$(( c < 4 ? c : 4 ))
    # shellcheck disable=SC2086  # $flags is a word list
    IFS='|' read -r k_rps k_p50 k_p99 k_req k_resp k_peaks k_note <<<"$(measure koma "$koma_runs" "$build/server/koma_server" --log_level=warn -- $flags --concurrency "$c" --channels "$channels")"
    # shellcheck disable=SC2086
    IFS='|' read -r e_rps e_p50 e_p99 _ e_resp _ e_note <<<"$(measure echo 1 "$build/bench/koma_echo_server" -- $flags --concurrency "$c" --channels "$channels")"
    if [ -n "${STRICT:-}" ] && [ -n "$k_note$e_note" ]; then
      echo "failed calls: $rpc $size c=$c: koma$k_note echo$e_note" >&2
      exit 1
    fi
    ratio=$(python3 -c "print('%.2f' % ($k_rps / $e_rps) if $e_rps > 0 else '-')")
    # The issue's budget: 64 MiB plus 3x the requests in flight (c calls, each holding its
    # request while it waits or runs).
    budget=$(python3 -c "print('%.0f' % (64 + 3 * $c * $k_req / 1048576))")
    echo "| $rpc | $size | $c | $k_rps$k_note | $e_rps$e_note | $ratio | $k_p50 / $k_p99 | $e_p50 / $e_p99 | $(mib "$k_req") | $(mib "$k_resp") / $(mib "$e_resp") | $k_peaks | $budget |"
  done
done

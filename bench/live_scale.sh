#!/usr/bin/env bash
# LiveLipBlink at scale (issue 44; docs/benchmarks.md, "LiveLipBlink: latency and streams"):
# koma_live_load replays N concurrent streams at real time against a fresh koma_server on
# 127.0.0.1 (port 0) for each N, and prints one row per N: frames, failed streams, each grid
# frame's lateness past the audio that decides it (budget: one grid frame, 41.7 ms, at p99),
# the total from the end of the frame's audio, and the server's CPU and memory per stream.
# The load tool and the server share the machine's cores as they are (nothing is pinned): on
# a 2-core host the client's CPU is part of what limits N (its column says how much).
#   bench/live_scale.sh                       N = 50 100 200 500 1000, 20 s each
#   SEARCH=1 bench/live_scale.sh              then bisect between the largest N within the
#                                             budget and the smallest over it (to STEP streams)
#   NS="100 300" DURATION=10 bench/live_scale.sh
#   LATENCY=1 bench/live_scale.sh             the latency mode instead: one stream per
#                                             lookahead 0..3 (DURATION default 60 s)
#   ECHO=1 SEARCH=1 bench/live_scale.sh       koma_echo_server's LiveLipBlink too, the transport-
#                                             only ceiling (bench/live_echo.h: a frame per grid
#                                             frame, no decoding or analysis): for each N the
#                                             echo, then koma, each on a fresh server; the largest
#                                             N of each (the bisection runs for each)
# NICE=-10: run the server and the tool at that niceness (negative: root), and this session's
# autogroup too where the kernel groups sessions (sched_autogroup: niceness alone then only ranks
# threads within the session), so that other work on a shared host (builds) delays them less;
# the figures then show the software more than the host. Default: the cores as they are.
# Environment: BUILD_DIR (default build), NS, DURATION (20), WARMUP (2), CHUNK_MS ("10,20":
# half the streams send 10 ms chunks, half 20 ms), LOOKAHEAD (2), STEP (25), SKIP_BUILD=1,
# PERF=N (record the server with perf for 10 s in the middle of the run with N streams:
# $work is removed on exit, so the flat report goes to PERF_OUT, default
# /tmp/koma-live-perf.txt, and perf.data next to it; with ECHO=1 the echo's as -echo.txt).
# Recordings: samples/voice.flac (16 kHz) and two made here with espeak-ng and sox (English at
# 48 kHz, Japanese at 16 kHz), each stream one of them in turn, looped.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
duration=${DURATION:-20}
warmup=${WARMUP:-2}
chunk_ms=${CHUNK_MS:-10,20}
lookahead=${LOOKAHEAD:-2}
step=${STEP:-25}
ns=${NS:-50 100 200 500 1000}
strict=""  # STRICT=1: exit 1 when a stream fails or a frame is missing (the ctest smoke)
[ "${STRICT:-0}" != 1 ] || strict=--fail_on_error
load=$build/bench/koma_live_load
server=$build/server/koma_server
echo_server=$build/bench/koma_echo_server
kinds=koma
[ "${ECHO:-0}" != 1 ] || kinds="echo koma"
# renice_server: every thread of the server (setpriority is per thread on Linux) to $NICE.
renice_server() {
  [ -n "${NICE:-}" ] || return 0
  local task
  for task in /proc/"$server_pid"/task/*; do renice -n "$NICE" -p "${task##*/}" >/dev/null; done
}
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($server_pid, $target), stop_server
if [ -n "${NICE:-}" ]; then
  load="nice -n $NICE $load"
  if [ -w /proc/self/autogroup ]; then  # the group outlives this script: restored on exit
    autogroup_nice=$(awk '{print $3}' /proc/self/autogroup)
    trap 'echo "$autogroup_nice" >/proc/self/autogroup; cleanup' EXIT
    echo "$NICE" >/proc/self/autogroup
  fi
fi

if [ "${SKIP_BUILD:-0}" != 1 ]; then
  targets="koma_live_load koma_server"
  [ "${ECHO:-0}" != 1 ] || targets="$targets koma_echo_server"
  # shellcheck disable=SC2086  # the targets are words
  flock /tmp/koma-build.lock cmake --build "$build" -j2 --target $targets >/dev/null
fi

# The recordings: silence around each sentence, as samples/make_voice.sh.
espeak-ng -v en-us+m3 -w "$work/en.wav" "the quick brown fox jumps over the lazy dog, twice"
espeak-ng -v ja+f3 -w "$work/ja.wav" "あしたはあめがふるかもしれません"
sox -n -r 48000 -c 1 -b 16 "$work/s48.wav" trim 0 0.6
sox "$work/en.wav" -r 48000 -b 16 "$work/en48.wav"
sox "$work/s48.wav" "$work/en48.wav" "$work/s48.wav" "$work/en48k.flac"
sox -n -r 16000 -c 1 -b 16 "$work/s16.wav" trim 0 0.3
sox "$work/ja.wav" -r 16000 -b 16 "$work/ja16.wav"
sox "$work/s16.wav" "$work/ja16.wav" "$work/s16.wav" "$work/ja16k.flac"
audio="$root/samples/voice.flac,$work/en48k.flac,$work/ja16k.flac"

# run KIND N [LOAD ARGS...]: a fresh server (KIND koma: koma_server; echo: koma_echo_server),
# N streams; the report is $work/KIND-N.json.
run() {
  local kind=$1 n=$2
  shift 2
  if [ "$kind" = echo ]; then
    start_server "$echo_server"
  else
    start_server "$server" --log_level=warn --live_max_streams=$((n + 10))
  fi
  renice_server
  local perf_pid=""
  if [ "${PERF:-}" = "$n" ]; then
    (sleep $((duration > 16 ? duration / 2 - 3 : 2)) && perf record -F 999 -e cpu-clock -g -p "$server_pid" \
      -o "$work/perf.data" -- sleep 10 >/dev/null 2>&1) &
    perf_pid=$!
  fi
  $load --target "$target" --streams "$n" --duration "$duration" --warmup "$warmup" \
    --audio "$audio" --chunk_ms "$chunk_ms" --lookahead "$lookahead" \
    --server_pid "$server_pid" --quiet --json "$work/$kind-$n.json" $strict "$@"
  if [ -n "$perf_pid" ]; then
    wait "$perf_pid" || true
    local out=${PERF_OUT:-/tmp/koma-live-perf.txt}
    [ "$kind" = koma ] || out=${out%.txt}-$kind.txt
    perf report -i "$work/perf.data" --no-children -g none --percent-limit 0.5 --stdio \
      >"$out" 2>/dev/null || true
    cp "$work/perf.data" "${out%.txt}.data"
    echo "perf report of the server at N=$n: $out (perf.data: ${out%.txt}.data)"
  fi
  stop_server
  row "$kind" "$work/$kind-$n.json"
}

row() {
  python3 - "$1" "$2" <<'PY'
import json, sys
r = json.load(open(sys.argv[2]))
s = r.get("server", {})
l, t = r["lateness_ms"], r["total_ms"]
print("%-4s %6d %8d %6d %7.2f %7.2f %8.2f %7.2f %8.2f %7.2f %8.1f %9.3f %7.3f %8.1f  %-6s %s" % (
    sys.argv[1], r["streams"], r["frames_measured"], r["streams_failed"], l["p50"], l["p99"], l["max"],
    r["lateness_from_write_ms"]["p99"], t["p99"], r["pacer_lag_ms"]["p99"], s.get("cpu_percent", 0), s.get("cpu_percent_per_stream", 0),
    s.get("mib_per_stream", 0), r.get("client_cpu_percent", 0),
    "within" if r["within_budget"] else "OVER", open("/proc/loadavg").read().split()[0]))
for what, count in sorted(r["errors"].items()):
    print("         %d streams failed: %s" % (count, what[:150]))
PY
}

within() { python3 -c 'import json,sys; sys.exit(0 if json.load(open(sys.argv[1]))["within_budget"] else 1)' "$work/$1-$2.json"; }

echo "koma_live_load against koma_server on 127.0.0.1 ($(nproc) cores shared by both, nothing pinned,"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg)); recordings: voice.flac 16 kHz, espeak-ng English"
echo "48 kHz, Japanese 16 kHz, looped; one connection per stream"
if [ "${LATENCY:-0}" = 1 ]; then
  duration=${DURATION:-60}  # not 20: p99 of ~1,400 frames per lookahead
  echo "one stream per lookahead 0..3, chunks ${CHUNK_MS:-20} ms, $duration s (first $warmup s not counted)"
  start_server "$server" --log_level=warn
  renice_server
  $load --target "$target" --streams 4 --lookahead 0,1,2,3 --duration "$duration" \
    --warmup "$warmup" --audio "$audio" --chunk_ms "${CHUNK_MS:-20}" --server_pid "$server_pid" \
    --json "$work/latency.json" $strict
  stop_server
  exit 0
fi
echo "chunks $chunk_ms ms, lookahead $lookahead, $duration s per N (first $warmup s not counted)"
echo "lat = arrival - the deciding chunk's send time (due), budget p99 <= 41.7 ms (one grid frame);"
echo "wr = the same from the chunk's write (the client's own stalls left out); tot = from the frame's"
echo "end; pacer = this client's lag handing chunks out (large: this client is starved of CPU)"
echo "srv       N   frames failed lat.p50 lat.p99  lat.max  wr.p99  tot.p99 pacer99 srv.CPU%  CPU%/str MiB/str cli.CPU%  budget load"
declare -A best worst lo hi
for kind in $kinds; do best[$kind]=0 worst[$kind]=0; done
for n in $ns; do
  for kind in $kinds; do
    run "$kind" "$n"
    if within "$kind" "$n"; then best[$kind]=$n; else [ "${worst[$kind]}" != 0 ] || worst[$kind]=$n; fi
  done
done
if [ "${SEARCH:-0}" = 1 ]; then
  # The bisections side by side: each round runs every kind still searching, the echo first.
  for kind in $kinds; do lo[$kind]=${best[$kind]} hi[$kind]=${worst[$kind]}; done
  searching=1
  while [ "$searching" = 1 ]; do
    searching=0
    for kind in $kinds; do
      if [ "${hi[$kind]}" = 0 ] || ((hi[$kind] - lo[$kind] <= step)); then continue; fi
      searching=1
      mid=$(((lo[$kind] + hi[$kind]) / 2 / step * step))
      ((mid > lo[$kind])) || mid=$((lo[$kind] + step))
      run "$kind" "$mid"
      if within "$kind" "$mid"; then lo[$kind]=$mid; else hi[$kind]=$mid; fi
    done
  done
  for kind in $kinds; do best[$kind]=${lo[$kind]}; done
fi
[ "${ECHO:-0}" != 1 ] || echo "largest N within the budget (echo, transport only): ${best[echo]}"
echo "largest N within the budget: ${best[koma]}"

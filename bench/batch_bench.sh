#!/usr/bin/env bash
# `koma batch` against its floor and its predecessor, side by side on one koma_server over
# loopback, 1,000 Pitch-size clips (copies of samples/pitch.bvh):
#   load   koma_load --rpc skeletal --input pitch.bvh -c JOBS --count 1000: calls/s of the
#          same payload with no files (the request built once), the floor
#   batch  koma batch skeletal CLIPS -o OUT --jobs JOBS: clips/s, wall clock of the whole
#          command (start, discovery, reads, calls, writes), outputs on the clips' disk
#   shm    the same with clips and outputs in /dev/shm (tmpfs): no disk in the figure
#   loop   a shell loop of single `koma skeletal` calls over LOOP_CLIPS of the clips: clips/s
# ROUNDS rounds per JOBS value, the order of the runs rotating each round; prints each round
# and the medians of the rates and of the per-round ratios batch/load and batch/loop.
#   bench/batch_bench.sh                        (ROUNDS=5 JOBS="2 8" LOOP_CLIPS=100)
#   ROUNDS=3 JOBS=4 BUILD_DIR=build bench/batch_bench.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
rounds=${ROUNDS:-5}
jobs_list=${JOBS:-2 8}
loop_clips=${LOOP_CLIPS:-100}
clips=${CLIPS:-1000}
koma=$build/client/koma
load=$build/bench/koma_load
pitch=$root/samples/pitch.bvh
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($server_pid, $target), stop_server
shm=""
if [ -d /dev/shm ] && [ -w /dev/shm ]; then
  shm=$(mktemp -d /dev/shm/koma_batch_bench.XXXXXX)
  trap 'rm -rf "$shm"; cleanup' EXIT
fi

mkdir -p "$work/clips"
for i in $(seq "$clips"); do cp "$pitch" "$work/clips/pitch_$i.bvh"; done
[ -z "$shm" ] || cp -r "$work/clips" "$shm/clips"
start_server "$build/server/koma_server" --log_level=warn

now() { date +%s.%N; }
rate() { python3 -c "print('%.1f' % ($1 / ($3 - $2)))"; }

run_load() {  # calls/s
  "$load" --rpc skeletal --input "$pitch" --target "$target" -c "$1" --count "$clips" \
    --deadline 60 --quiet --fail-on-error --json "$work/load.json"
  python3 -c 'import json, sys; print("%.1f" % json.load(open(sys.argv[1]))["rps"])' "$work/load.json"
}
run_batch() {  # clips/s: JOBS CLIP_DIR OUT_DIR
  rm -rf "$3"
  local t0 t1
  t0=$(now)
  "$koma" batch skeletal "$2" -o "$3" --server "$target" --jobs "$1" --quiet
  t1=$(now)
  rate "$clips" "$t0" "$t1"
}
run_loop() {  # clips/s
  rm -rf "$work/loop"
  mkdir "$work/loop"
  local t0 t1
  t0=$(now)
  for i in $(seq "$loop_clips"); do
    "$koma" skeletal "$work/clips/pitch_$i.bvh" -o "$work/loop/pitch_$i.bvh" --server "$target" \
      >/dev/null
  done
  t1=$(now)
  rate "$loop_clips" "$t0" "$t1"
}

echo "$clips Pitch-size clips ($(wc -c <"$pitch") bytes each), server $target, $(nproc) cores"
for jobs in $jobs_list; do
  : >"$work/rows"
  for round in $(seq "$rounds"); do
    kinds="load batch shm loop"
    for _ in $(seq $(((round - 1) % 4))); do kinds="${kinds#* } ${kinds%% *}"; done  # rotate
    declare -A r=([shm]=0)
    for kind in $kinds; do
      case $kind in
        load) r[load]=$(run_load "$jobs") ;;
        batch) r[batch]=$(run_batch "$jobs" "$work/clips" "$work/out") ;;
        shm) [ -z "$shm" ] || r[shm]=$(run_batch "$jobs" "$shm/clips" "$shm/out") ;;
        loop) r[loop]=$(run_loop) ;;
      esac
    done
    echo "${r[load]} ${r[batch]} ${r[shm]} ${r[loop]}" >>"$work/rows"
    echo "jobs $jobs round $round ($kinds): load ${r[load]} calls/s | batch ${r[batch]} clips/s" \
      "| batch in /dev/shm ${r[shm]} clips/s | loop ${r[loop]} clips/s"
  done
  python3 - "$jobs" "$work/rows" <<'PY'
import statistics, sys
jobs, path = sys.argv[1], sys.argv[2]
rows = [list(map(float, line.split())) for line in open(path)]
med = lambda xs: statistics.median(xs)
load, batch, shm, loop = (med([r[i] for r in rows]) for i in range(4))
print(f"jobs {jobs}, medians of {len(rows)} rounds: load {load:.0f} calls/s, batch {batch:.0f} "
      f"clips/s, batch in /dev/shm {shm:.0f} clips/s, loop {loop:.1f} clips/s")
print(f"  batch/load {med([r[1] / r[0] for r in rows]):.2f}, batch(/dev/shm)/load "
      f"{med([r[2] / r[0] for r in rows]):.2f}, batch/loop {med([r[1] / r[3] for r in rows]):.1f}x")
PY
done
stop_server

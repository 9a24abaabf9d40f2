#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/) for a bounded time under ASan + UBSan:
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]      (default 60 s, every target)
# e.g. scripts/fuzz.sh 600 bvh motion3
#
# Each target starts from its seed corpus (fuzz/make_seeds.cc: tests/testdata and samples) and
# the reproducers of earlier findings (fuzz/regressions/TARGET/), growing a working corpus in
# $build/fuzz-corpus/TARGET. A crash, sanitizer report, failed round-trip check, timeout
# (> 10 s on one input) or an input needing > 2 GiB is a finding: the input is saved as
# $build/fuzz-findings/TARGET-crash-<sha1> (also with KOMA_FUZZ_ARTIFACTS=DIR, for CI), the
# other targets still run, and the script exits 1. Reproduce with
#   build-asan/fuzz/TARGET_fuzz FILE
# Prints one line per target: runs, executions per second, coverage (edges) and corpus size.
# Targets run $KOMA_FUZZ_JOBS at a time (default: one per core), each for SECONDS.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_ASAN_BUILD_DIR:-$root/build-asan}
seconds=${1:-60}
shift || true
all=(bvh motion3 curve_csv spine gltf fbx audio retime_skeletal retime_curves lip_blink)
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=("${all[@]}"); fi

binaries=(koma_fuzz_seeds)
for t in "${targets[@]}"; do binaries+=("${t}_fuzz"); done
"$root/scripts/sanitizer-build.sh" asan "${binaries[@]}"

seeds=$build/fuzz-seeds
rm -rf "$seeds"
"$build/fuzz/koma_fuzz_seeds" "$root/tests/testdata" "$root/samples" "$seeds" >/dev/null
/usr/bin/python3 "$root/fuzz/make_cost_seeds.py" "$seeds"  # the cost cases (issue 42)
findings=${KOMA_FUZZ_ARTIFACTS:-$build/fuzz-findings}
mkdir -p "$findings"
rm -f "$build"/fuzz-*.rc

dict_of() {
  case "$1" in
    bvh) echo "-dict=$root/fuzz/bvh.dict" ;;
    motion3|curve_csv) echo "-dict=$root/fuzz/motion3.dict" ;;
    spine) echo "-dict=$root/fuzz/spine.dict" ;;
  esac
}

# fuzz_one TARGET: runs it, prints its line, leaves TARGET.rc (0 = no finding).
fuzz_one() {
  local t=$1 corpus=$build/fuzz-corpus/$1 log=$build/fuzz-$1.log rc=0
  mkdir -p "$corpus"
  local inputs=("$corpus" "$seeds/$t")
  if [ -d "$root/fuzz/regressions/$t" ]; then inputs+=("$root/fuzz/regressions/$t"); fi
  # Leak checking stays on (ASan's default): a leak on one input is a finding too.
  # shellcheck disable=SC2046
  "$build/fuzz/${t}_fuzz" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 $(dict_of "$t") \
    -artifact_prefix="$findings/$t-" "${inputs[@]}" >"$log" 2>&1 || rc=$?
  local runs rate last cov corp
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  if [ "$rc" -eq 0 ]; then
    echo "fuzz $t: ok, ${seconds}s, ${runs:-?} runs, ${rate:-?} exec/s, cov ${cov:-?} edges, corpus ${corp:-?}"
  else
    {
      echo "fuzz $t: FINDING (exit $rc); reproducer(s):"
      ls "$findings/$t-"* 2>/dev/null || echo "  (none saved; see $log)"
      grep -E 'ERROR: |SUMMARY: |fuzz check failed|runtime error' "$log" | head -5 || true
    } >&2
  fi
  echo "$rc" >"$build/fuzz-$t.rc"
}

# $KOMA_FUZZ_JOBS targets at a time (default: one per core).
jobs=${KOMA_FUZZ_JOBS:-$(nproc)}
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  fuzz_one "$t" &
  running=$((running + 1))
done
wait

failed=()
for t in "${targets[@]}"; do
  [ "$(cat "$build/fuzz-$t.rc" 2>/dev/null || echo 1)" = 0 ] || failed+=("$t")
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}; logs in $build/fuzz-<target>.log, inputs in $findings" >&2
  exit 1
fi

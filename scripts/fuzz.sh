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
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_ASAN_BUILD_DIR:-$root/build-asan}
seconds=${1:-60}
shift || true
all=(bvh motion3 curve_csv retime_skeletal retime_curves lip_blink)
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=("${all[@]}"); fi

binaries=(koma_fuzz_seeds)
for t in "${targets[@]}"; do binaries+=("${t}_fuzz"); done
"$root/scripts/sanitizer-build.sh" asan "${binaries[@]}"

seeds=$build/fuzz-seeds
rm -rf "$seeds"
"$build/fuzz/koma_fuzz_seeds" "$root/tests/testdata" "$root/samples" "$seeds" >/dev/null
findings=${KOMA_FUZZ_ARTIFACTS:-$build/fuzz-findings}
mkdir -p "$findings"

dict_of() {
  case "$1" in
    bvh) echo "-dict=$root/fuzz/bvh.dict" ;;
    motion3|curve_csv) echo "-dict=$root/fuzz/motion3.dict" ;;
  esac
}

failed=()
for t in "${targets[@]}"; do
  corpus=$build/fuzz-corpus/$t
  mkdir -p "$corpus"
  inputs=("$corpus" "$seeds/$t")
  if [ -d "$root/fuzz/regressions/$t" ]; then inputs+=("$root/fuzz/regressions/$t"); fi
  log=$build/fuzz-$t.log
  # Leak checking stays on (ASan's default): a leak on one input is a finding too.
  set +e
  # shellcheck disable=SC2046
  "$build/fuzz/${t}_fuzz" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 $(dict_of "$t") \
    -artifact_prefix="$findings/$t-" "${inputs[@]}" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9a-zA-Z]*\).*/\1/p' <<<"$last")
  if [ "$rc" -eq 0 ]; then
    echo "fuzz $t: ok, ${seconds}s, ${runs:-?} runs, ${rate:-?} exec/s, cov ${cov:-?} edges, corpus ${corp:-?}"
  else
    echo "fuzz $t: FINDING (exit $rc); reproducer(s):" >&2
    ls "$findings/$t-"* >&2 2>/dev/null || echo "  (none saved; see $log)" >&2
    grep -E 'ERROR: |SUMMARY: |fuzz check failed|runtime error' "$log" | head -5 >&2 || true
    failed+=("$t")
  fi
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}; logs in $build/fuzz-<target>.log, inputs in $findings" >&2
  exit 1
fi

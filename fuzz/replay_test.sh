#!/usr/bin/env bash
# ctest fuzz.TARGET_replay (ASan + UBSan build): runs a fuzz target once over its seed corpus
# (fuzz/make_seeds.cc, and fuzz/make_cost_seeds.py's cost cases) and over fuzz/regressions/TARGET/, the saved inputs of earlier findings,
# without fuzzing. A crash, sanitizer report or failed round-trip check fails the test.
#   replay_test.sh MAKE_SEEDS FUZZER TARGET TESTDATA_DIR SAMPLES_DIR REGRESSIONS_DIR
set -euo pipefail
make_seeds=$1 fuzzer=$2 target=$3 testdata=$4 samples=$5 regressions=$6
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$make_seeds" "$testdata" "$samples" "$work" >/dev/null
/usr/bin/python3 "$(dirname "$0")/make_cost_seeds.py" "$work"
inputs=("$work/$target")
if [ -d "$regressions/$target" ]; then inputs+=("$regressions/$target"); fi
"$fuzzer" -runs=0 "${inputs[@]}" 2>&1 | grep -E 'INITED|Done' || true
exit "${PIPESTATUS[0]}"

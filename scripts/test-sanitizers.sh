#!/usr/bin/env bash
# The test suite under sanitizers (docs/reliability.md), built with Debian's clang:
#   scripts/test-sanitizers.sh [asan|tsan|all]      (default all)
#
# asan: ASan + UBSan with no recovery (the first report aborts the process, so the test
#       fails), leak checking on, in build-asan: every unit, property, in-process gRPC and
#       end-to-end test, except the container image (label image: minutes of buildah), the
#       report pages in headless Chromium (label browser: they test the browser's rendering
#       of pages the report tests already check byte for byte; 2 min under ASan), and the
#       benchmarks and fault tests (they need bench/, which this build leaves out; the fault
#       tests run in the ordinary build).
# tsan: TSan in build-tsan, on the tests whose threads koma itself starts and synchronises:
#       the worker pool, the idle trimmer, the memory budget's concurrent reservations,
#       forward kinematics split over threads and the huge-page pool. Not the gRPC tests:
#       Debian's libgrpc is not built with TSan, so TSan cannot see its internal locking and
#       reports races inside gRPC that are not there; a run that is all noise proves nothing.
# Exit code: non-zero when a build or any test fails.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
what=${1:-all}
asan_build=${KOMA_ASAN_BUILD_DIR:-$root/build-asan}
tsan_build=${KOMA_TSAN_BUILD_DIR:-$root/build-tsan}

# Reports name file and line (llvm-symbolizer), and a second copy goes to the test's output.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
# Leaks inside OpenSSL held by Debian's (uninstrumented) gRPC at a client's exit: lsan.supp.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/scripts/lsan.supp:print_suppressions=0}
if command -v llvm-symbolizer >/dev/null; then
  export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-$(command -v llvm-symbolizer)}
fi

run_asan() {
  local start=$SECONDS
  "$root/scripts/sanitizer-build.sh" asan
  echo "test-sanitizers: ASan + UBSan build took $((SECONDS - start)) s"
  start=$SECONDS
  # Tests that time the server's answers stretch their bounds by KOMA_TEST_TIME_SCALE.
  KOMA_TEST_TIME_SCALE=4 ctest --test-dir "$asan_build" --output-on-failure -j"$(nproc)" \
    -LE 'image|bench|browser|setup'
  echo "test-sanitizers: ASan + UBSan tests took $((SECONDS - start)) s"
}

# TSan's binaries and, for each, the gtest filter of its tests of koma's own threads. Left out:
# IdleTrimmerTest.TheServerTrimsAfterItsCalls, which starts an in-process gRPC server (TSan
# reports a race on an epoll descriptor inside libgrpc's event engine: see above).
tsan_tests=(
  "tests/server/koma_tsan_threads_test WorkerPoolTest.*:IdleTrimmerTest.*:MemoryBudgetTest.*:DefaultBudgetTest.*-IdleTrimmerTest.TheServerTrimsAfterItsCalls"
  "tests/platform/thread_task_runner_test *"
  "tests/platform/huge_page_pool_test *"
)

run_tsan() {
  local start=$SECONDS targets=() entry
  for entry in "${tsan_tests[@]}"; do targets+=("$(basename "${entry%% *}")"); done
  "$root/scripts/sanitizer-build.sh" tsan "${targets[@]}"
  echo "test-sanitizers: TSan build took $((SECONDS - start)) s"
  start=$SECONDS
  local failed=0 binary filter
  for entry in "${tsan_tests[@]}"; do
    binary=${entry%% *}
    filter=${entry#* }
    echo "test-sanitizers: TSan: $binary --gtest_filter=$filter"
    if ! "$tsan_build/$binary" --gtest_filter="$filter" --gtest_brief=1; then
      echo "test-sanitizers: TSan: $binary failed" >&2
      failed=1
    fi
  done
  echo "test-sanitizers: TSan tests took $((SECONDS - start)) s"
  return $failed
}

case "$what" in
  asan) run_asan ;;
  tsan) run_tsan ;;
  all) run_asan; run_tsan ;;
  *) echo "usage: test-sanitizers.sh [asan|tsan|all]" >&2; exit 2 ;;
esac

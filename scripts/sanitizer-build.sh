#!/usr/bin/env bash
# Configures and builds koma with clang under sanitizers, for scripts/test-sanitizers.sh and
# scripts/fuzz.sh:
#   scripts/sanitizer-build.sh asan [TARGET...]   ASan + UBSan (no recovery) and libFuzzer's
#                                                 coverage, in build-asan (or $KOMA_ASAN_BUILD_DIR)
#   scripts/sanitizer-build.sh tsan [TARGET...]   TSan, in build-tsan (or $KOMA_TSAN_BUILD_DIR)
# With no TARGET, everything. -O1 with line tables: fast enough to run the whole test suite,
# and every report names file and line. Assertions stay on (no NDEBUG).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
kind=${1:?usage: sanitizer-build.sh asan|tsan [TARGET...]}
shift
case "$kind" in
  asan) build=${KOMA_ASAN_BUILD_DIR:-$root/build-asan}
        flags=(-DKOMA_SANITIZE=address,undefined -DKOMA_BUILD_FUZZERS=ON) ;;
  tsan) build=${KOMA_TSAN_BUILD_DIR:-$root/build-tsan}
        flags=(-DKOMA_SANITIZE=thread -DKOMA_BUILD_FUZZERS=OFF) ;;
  *) echo "sanitizer-build.sh: unknown kind '$kind' (asan or tsan)" >&2; exit 2 ;;
esac
"$root/scripts/install-deps.sh"
setup=()
if command -v ccache >/dev/null; then setup=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# A new build folder uses Ninja (an existing one keeps its generator).
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then setup+=(-G Ninja); fi
cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
  "-DCMAKE_CXX_FLAGS_DEBUG=-O1 -gline-tables-only" -DKOMA_BUILD_BENCH=OFF \
  "${setup[@]}" "${flags[@]}" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build" -j"$(nproc)" "${targets[@]}"

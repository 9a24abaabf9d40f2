#!/usr/bin/env bash
# Installs missing Debian packages, configures and builds koma in ./build (or $KOMA_BUILD_DIR).
#   build.sh              every dependency (scripts/install-deps.sh) and every target: the
#                         programs, the tests, the benchmarks, the Python package (test.sh)
#   build.sh --programs   only what the main job needs: the build dependencies
#                         (install-deps.sh --build-only) and the two programs, koma_server and
#                         koma (run-sample.sh). A new build folder is configured without the
#                         tests and benchmarks (their packages may be missing); an existing one
#                         keeps its configuration, so a later `build.sh` builds the rest.
# The build type is $KOMA_BUILD_TYPE, else the build folder's own (a rerun never switches a
# configured Release build to another type and rebuilds it all), else RelWithDebInfo.
# With KOMA_BUILD_LOG=FILE the compiler output goes to FILE (its tail is shown on failure).
# The full build also assembles the Python package in $build/python (python/CMakeLists.txt:
# stubs from proto/ by Debian's protoc + grpc_python_plugin); use it with
# PYTHONPATH=$build/python.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_BUILD_DIR:-$root/build}
programs_only=0
case "${1:-}" in
  --programs) programs_only=1 ;;
  "") ;;
  *) echo "usage: build.sh [--programs]" >&2; exit 2 ;;
esac
if [ "$programs_only" = 1 ]; then
  "$root/scripts/install-deps.sh" --build-only
else
  "$root/scripts/install-deps.sh"
fi
configured_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null || true)
build_type=${KOMA_BUILD_TYPE:-${configured_type:-RelWithDebInfo}}
# A new build folder uses Ninja (an existing one keeps the generator it was configured with);
# compiles go through ccache when it is installed (a rebuild of unchanged files is a cache hit).
setup=()
if [ ! -f "$build/CMakeCache.txt" ] && command -v ninja >/dev/null; then setup=(-G Ninja); fi
if command -v ccache >/dev/null; then setup+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
build_steps() {
  if [ "$programs_only" = 1 ]; then
    local options=()
    if [ ! -f "$build/CMakeCache.txt" ]; then
      options=(-DKOMA_BUILD_TESTS=OFF -DKOMA_BUILD_BENCH=OFF)
    fi
    cmake -S "$root" -B "$build" "${setup[@]}" -DCMAKE_BUILD_TYPE="$build_type" "${options[@]}"
    cmake --build "$build" -j"$(nproc)" --target koma_server koma
  else
    cmake -S "$root" -B "$build" "${setup[@]}" -DCMAKE_BUILD_TYPE="$build_type" \
      -DKOMA_BUILD_TESTS=ON -DKOMA_BUILD_BENCH=ON
    cmake --build "$build" -j"$(nproc)"
  fi
}
if [ -n "${KOMA_BUILD_LOG:-}" ]; then
  echo "building koma in $build (compiler output: $KOMA_BUILD_LOG)"
  if ! build_steps >"$KOMA_BUILD_LOG" 2>&1; then
    tail -n 40 "$KOMA_BUILD_LOG" >&2
    echo "build failed; full output in $KOMA_BUILD_LOG" >&2
    exit 1
  fi
else
  build_steps
fi
# Debian's python3 finds the `koma` package of this build with no further step: a koma.pth in
# its user site-packages names $build/python (the last build of any clone wins; docs/python.md).
# KOMA_NO_PTH=1 leaves the user site alone (then use PYTHONPATH=$build/python).
if [ -f "$build/python/koma/v1/retime_pb2.py" ] && [ -z "${KOMA_NO_PTH:-}" ] &&
   [ -x /usr/bin/python3 ]; then
  site=$(/usr/bin/python3 -m site --user-site)
  if mkdir -p "$site" 2>/dev/null && echo "$build/python" > "$site/koma.pth"; then
    echo "Python package: /usr/bin/python3 imports koma from $build/python ($site/koma.pth)"
  else
    echo "Python package: export PYTHONPATH=$build/python   (docs/python.md)"
  fi
fi

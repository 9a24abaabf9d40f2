#!/usr/bin/env bash
# Installs missing Debian packages, configures and builds koma in ./build (or $KOMA_BUILD_DIR).
# With KOMA_BUILD_LOG=FILE the compiler output goes to FILE (its tail is shown on failure).
# The build also assembles the Python package in $build/python (python/CMakeLists.txt: stubs
# from proto/ by Debian's protoc + grpc_python_plugin); use it with PYTHONPATH=$build/python.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_BUILD_DIR:-$root/build}
"$root/scripts/install-deps.sh"
build_steps() {
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${KOMA_BUILD_TYPE:-RelWithDebInfo}"
  cmake --build "$build" -j"$(nproc)"
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
if [ -f "$build/python/koma/v1/retime_pb2.py" ]; then
  echo "Python package: export PYTHONPATH=$build/python   (docs/python.md)"
fi

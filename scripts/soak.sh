#!/usr/bin/env bash
# Soak test, not part of CI (ctest's e2e.soak_smoke runs the same for 30 s): koma_server under
# a steady mix of all three RPCs for SECONDS (default 600), failing if a call fails or the
# server's RSS grows in the last third of the run (tests/e2e/soak_test.sh). Uses the binaries
# of ./build (or $KOMA_BUILD_DIR); run scripts/build.sh first.
#   scripts/soak.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_BUILD_DIR:-$root/build}
exec "$root/tests/e2e/soak_test.sh" "$build/server/koma_server" "$build/bench/koma_load" \
  "$root/samples/pitch.bvh" "$root/samples/arm_head.motion3.json" \
  "$root/samples/talk_blink.motion3.json" "${1:-600}"

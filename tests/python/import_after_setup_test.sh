#!/usr/bin/env bash
# Issue 18's acceptance line, as a user types it after the README's set-up: Debian's python3,
# no PYTHONPATH, `import koma` finds this build's package (through the koma.pth that
# scripts/build.sh writes) and retimes a sample through a real server on loopback.
#   import_after_setup_test.sh KOMA_SERVER PYTHON_PACKAGE_DIR SAMPLES_DIR
set -euo pipefail
server_bin=$1
package_dir=$2
samples=$3
# shellcheck source=../e2e/lib.sh
. "$(dirname "$0")/../e2e/lib.sh"

start_server "$server_bin"
cd "$(dirname "$samples")"
out=$(env -u PYTHONPATH timeout 60 /usr/bin/python3 -c "
import koma
print(koma.__file__)
print(koma.Client('$target', timeout=30).retime_skeletal('samples/pitch.bvh').counts)
" 2>&1) || fail "import koma without PYTHONPATH: $out (scripts/build.sh writes the koma.pth that makes this work)"
echo "$out"
first=$(echo "$out" | head -n 1)
case "$first" in
  "$package_dir"/koma/*) ;;
  *) fail "import koma found $first, not this build's package under $package_dir (another clone's koma.pth? rerun scripts/build.sh)" ;;
esac
echo "$out" | tail -n 1 | grep -q "'frames': 130" || fail "unexpected counts: $out"
stop_server
echo "PASS: /usr/bin/python3 imports koma from $package_dir and retimes samples/pitch.bvh"

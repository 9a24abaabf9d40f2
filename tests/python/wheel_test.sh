#!/usr/bin/env bash
# The `koma` wheel as a TD installs it: `pip install koma-VERSION-py3-none-any.whl` into a fresh
# venv that sees the system's site-packages (grpcio and protobuf from Debian's python3-grpcio
# and python3-protobuf; pip downloads nothing: --no-index), then the installed package (not the
# build's) retimes the sample against the real koma_server on loopback, byte for byte what the
# C++ CLI writes, and `python -m koma` works. Also: the wheel holds the generated stubs, its
# version is the project's, and it requires grpcio and protobuf.
# Usage: wheel_test.sh WHEEL VERSION KOMA_SERVER KOMA SAMPLES_DIR
set -euo pipefail
wheel=$(realpath "$1") version=$2 server_bin=$(realpath "$3") client_bin=$(realpath "$4")
samples=$(realpath "$5")
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../e2e/lib.sh
source "$here/../e2e/lib.sh"

[ -f "$wheel" ] || fail "no $wheel (build the koma_wheel target)"
[ "$(basename "$wheel")" = "koma-$version-py3-none-any.whl" ] || fail "wheel name $(basename "$wheel")"

# 1. What the wheel holds.
/usr/bin/python3 - "$wheel" "$version" <<'PY' || fail "the wheel's contents"
import sys, zipfile
wheel, version = sys.argv[1:]
names = set(zipfile.ZipFile(wheel).namelist())
# _formats.py: the format table the build exports from C++ (formats/format_table_export.cc).
for want in ("koma/__init__.py", "koma/_client.py", "koma/_version.py", "koma/_health_pb2.py",
             "koma/_formats.py", "koma/_format_table.py",
             "koma/v1/__init__.py", "koma/v1/retime_pb2.py", "koma/v1/retime_pb2_grpc.py",
             "koma/v1/motion_pb2.py", f"koma-{version}.dist-info/METADATA"):
    assert want in names, f"{want} not in the wheel: {sorted(names)}"
assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")], names
metadata = zipfile.ZipFile(wheel).read(f"koma-{version}.dist-info/METADATA").decode()
assert f"\nVersion: {version}\n" in metadata, metadata
requires = sorted(l.split(": ", 1)[1] for l in metadata.splitlines() if l.startswith("Requires-Dist"))
assert [r.replace(" (", "").replace(")", "") for r in requires] == ["grpcio>=1.48", "protobuf>=3.20"], requires
print(f"wheel: {len(names)} files, requires {requires}")
PY

# 2. A fresh venv with the system's packages, the wheel installed offline.
cd "$work"
/usr/bin/python3 -m venv --system-site-packages "$work/venv" || fail "python3 -m venv"
venv_python=$work/venv/bin/python
env -u PYTHONPATH "$venv_python" -m pip install --no-index --no-cache-dir --quiet "$wheel" \
  >"$work/pip.log" 2>&1 || fail "pip install: $(cat "$work/pip.log")"
env -u PYTHONPATH "$venv_python" -m pip show koma >"$work/show.txt" || fail "pip show koma"
grep -qx "Version: $version" "$work/show.txt" || fail "pip show: $(cat "$work/show.txt")"

# 3. The installed package against the real server: the same bytes as the C++ CLI.
start_server "$server_bin" --log_level=warn
"$client_bin" skeletal "$samples/pitch.bvh" -o "$work/cli.bvh" --server "$target" >/dev/null ||
  fail "koma skeletal"
env -u PYTHONPATH "$venv_python" - "$target" "$samples/pitch.bvh" "$work" "$version" <<'PY' ||
import os, sys
import koma
target, pitch, work, version = sys.argv[1:]
site = os.path.join(work, "venv", "lib")
assert os.path.realpath(koma.__file__).startswith(os.path.realpath(site) + os.sep), koma.__file__
assert koma.__version__ == version, koma.__version__
with koma.Client(target, timeout=60) as client:
    result = client.retime_skeletal(pitch)
    result.write(os.path.join(work, "py.bvh"))
print(f"koma {koma.__version__} from {os.path.dirname(koma.__file__)}: {result.counts}")
PY
  fail "the installed package"
cmp "$work/cli.bvh" "$work/py.bvh" || fail "the wheel's BVH differs from the CLI's"
env -u PYTHONPATH "$venv_python" -m koma health --server "$target" >"$work/health.txt" ||
  fail "python -m koma health: $(cat "$work/health.txt")"
grep -qx SERVING "$work/health.txt" || fail "python -m koma health: $(cat "$work/health.txt")"
stop_server
echo "PASS: koma $version wheel installed offline in a fresh venv; same bytes as the CLI"

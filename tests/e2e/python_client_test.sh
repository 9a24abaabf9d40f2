#!/usr/bin/env bash
# Interop: the real koma_server on a free loopback port, called from python3-grpcio with
# stubs generated from proto/ by protoc.
# Usage: python_client_test.sh KOMA_SERVER PROTOC PROTO_DIR PYTHON3
set -euo pipefail
server_bin=$1 protoc_bin=$2 proto_dir=$3 python=$4
here=$(cd "$(dirname "$0")" && pwd)

work=$(mktemp -d)
server_pid=""
cleanup() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then kill -KILL "$server_pid"; fi
  rm -rf "$work"
}
trap cleanup EXIT

mkdir -p "$work/gen"
"$protoc_bin" -I "$proto_dir" --python_out="$work/gen" "$proto_dir"/koma/v1/*.proto

"$server_bin" --address=127.0.0.1:0 --port_file="$work/port" 2>"$work/server.log" &
server_pid=$!
for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
[ -s "$work/port" ] || { cat "$work/server.log" >&2; echo "FAIL: no port" >&2; exit 1; }

timeout 60 "$python" "$here/python_client.py" "$(cat "$work/port")" "$work/gen"

kill -TERM "$server_pid"
wait "$server_pid"
server_pid=""

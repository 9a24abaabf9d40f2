#!/usr/bin/env bash
# Interop: the real koma_server on a free loopback port, called from python3-grpcio with
# stubs generated from proto/ by protoc.
# Usage: python_client_test.sh KOMA_SERVER PROTOC PROTO_DIR PYTHON3
set -euo pipefail
server_bin=$1 protoc_bin=$2 proto_dir=$3 python=$4
here=$(cd "$(dirname "$0")" && pwd)

# shellcheck source=lib.sh
source "$here/lib.sh"

mkdir -p "$work/gen"
"$protoc_bin" -I "$proto_dir" --python_out="$work/gen" "$proto_dir"/koma/v1/*.proto

start_server "$server_bin"

timeout 60 "$python" "$here/python_client.py" "${target##*:}" "$work/gen"

stop_server

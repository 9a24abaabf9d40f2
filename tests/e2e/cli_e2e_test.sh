#!/usr/bin/env bash
# The `koma` CLI end to end (tests/e2e/cli_cases.py) against the real koma_server on a free
# loopback port. Usage: cli_e2e_test.sh KOMA_SERVER KOMA PYTHON SAMPLES_DIR SCHEMA
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 samples=$4 schema=$5

source "$(dirname "$0")/lib.sh"

start_server "$server_bin" --worker_threads=2
mkdir "$work/cases"
"$python" "$(dirname "$0")/cli_cases.py" "$client_bin" "$target" "$samples" "$schema" \
  "$work/cases" || fail "cli_cases.py"
stop_server
echo "PASS: koma CLI end to end"

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

# `koma health --json` reports the serving status as "status": a draining server (SIGTERM, still
# answering during --shutdown_delay_ms) is NOT_SERVING there, with exit code 1, never "ok".
start_server_as draining "$server_bin" --shutdown_delay_ms=30000 --shutdown_grace_ms=0
kill -TERM "$pid_draining"
not_serving() {
  local code=0
  "$client_bin" health --server "$target_draining" --json >"$work/health.json" 2>/dev/null ||
    code=$?
  [ "$code" = 1 ] && grep -q '"serving_status":"NOT_SERVING"' "$work/health.json"
}
wait_until 10 not_serving || fail "health --json never said NOT_SERVING: $(cat "$work/health.json")"
"$python" - "$work/health.json" "$schema" <<'PY' || fail "health --json on a draining server"
import json, sys
import jsonschema
health = json.load(open(sys.argv[1]))
jsonschema.validate(health, json.load(open(sys.argv[2])))
assert health["status"] == "NOT_SERVING", health
PY
kill_server_as draining
echo "PASS: koma CLI end to end"

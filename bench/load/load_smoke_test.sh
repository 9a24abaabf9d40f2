#!/usr/bin/env bash
# bench.load_smoke: koma_load for ~2 s against koma_server and koma_echo_server (both on a
# free loopback port), skeletal 129 frames x 31 joints at concurrency 4; each JSON report
# must show calls and no errors, and each server must exit 0 on SIGTERM.
#   load_smoke_test.sh KOMA_LOAD KOMA_SERVER KOMA_ECHO_SERVER
set -euo pipefail
load_bin=$1
koma_server_bin=$2
echo_server_bin=$3

here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../../tests/e2e/lib.sh
source "$here/../../tests/e2e/lib.sh"  # $work, fail, start_server, stop_server

# Checks the report at $1: count > 0, every call ok, no errors.
check_report() {
  python3 - "$1" <<'PY' || fail "bad report $1: $(cat "$1")"
import json, sys
r = json.load(open(sys.argv[1]))
assert r["count"] > 0, "count is 0"
assert r["ok"] == r["count"], "not every call ok"
assert r["errors"] == {}, "errors: %s" % r["errors"]
assert 0 < r["latency_ms"]["p50"] <= r["latency_ms"]["p99"] <= r["latency_ms"]["max"]
assert 0 < r["response_bytes"]["min"] <= r["response_bytes"]["max"], r["response_bytes"]
PY
}

run_load() {  # run_load NAME
  "$load_bin" --rpc skeletal --frames 129 --joints 31 --concurrency 4 --channels 2 \
    --duration 2 --warmup 0.2 --deadline 10 --target "$target" --json "$work/$1.json" \
    --fail-on-error >"$work/$1.txt" || fail "koma_load against $1 exited $?: $(cat "$work/$1.txt")"
  check_report "$work/$1.json"
  echo "$1: $(python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print(r["count"], "calls,", round(r["rps"]), "RPS, p50", round(r["latency_ms"]["p50"], 3), "ms")' "$work/$1.json")"
}

start_server "$koma_server_bin" --log_level=warn
run_load koma
stop_server

rm -f "$work/port"
start_server "$echo_server_bin"
run_load echo
stop_server

# Usage errors exit 2.
code=0
"$load_bin" --rpc nonsense >/dev/null 2>&1 || code=$?
[ "$code" = 2 ] || fail "koma_load --rpc nonsense exited $code, expected 2"
echo "PASS"

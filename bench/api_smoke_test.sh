#!/usr/bin/env bash
# bench.api_smoke: koma_server and every koma_api_server --api variant on free loopback
# ports, all at once; koma_api_check sends each the same calls of every RPC (and one invalid
# request) and fails unless all answer koma_server's status and response bytes; then every
# server must exit 0 on SIGTERM. A few seconds.
#   api_smoke_test.sh KOMA_API_CHECK KOMA_SERVER KOMA_API_SERVER
set -euo pipefail
check_bin=$1
koma_server_bin=$2
api_server_bin=$3

work=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  tail -n 20 "$work"/*.log >&2 || true
  exit 1
}

# start NAME BINARY [FLAGS...]: appends the server's pid to $pids and its target to $targets.
targets=()
start() {
  local name=$1
  shift
  "$@" --address=127.0.0.1:0 --port_file="$work/$name.port" 2>"$work/$name.log" &
  pids+=($!)
  for _ in $(seq 100); do [ -s "$work/$name.port" ] && break; sleep 0.1; done
  [ -s "$work/$name.port" ] || fail "$name did not write its port within 10 s"
  targets+=("127.0.0.1:$(cat "$work/$name.port")")
}

start koma "$koma_server_bin" --log_level=warn
start sync "$api_server_bin" --api=sync
start sync2 "$api_server_bin" --api=sync --worker_threads=2
start callback_inline "$api_server_bin" --api=callback_inline
start callback_pool "$api_server_bin" --api=callback_pool --worker_threads=2
start async "$api_server_bin" --api=async --worker_threads=2

"$check_bin" "${targets[@]}" || fail "koma_api_check: the variants do not answer like koma_server"

for p in "${pids[@]}"; do
  kill -TERM "$p"
  code=0
  wait "$p" || code=$?
  [ "$code" = 0 ] || fail "server $p exited $code after SIGTERM"
done
pids=()

# A usage error exits non-zero and names the flag.
if "$api_server_bin" --api=nonsense 2>"$work/usage.log"; then fail "--api=nonsense started"; fi
grep -q -- "--api" "$work/usage.log" || fail "--api=nonsense: $(cat "$work/usage.log")"
echo "PASS"

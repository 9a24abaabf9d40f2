#!/usr/bin/env bash
# End to end: the real koma_server with --http_port on loopback, driven by curl. Each unary RPC
# on the sample files in JSON and in binary: the binary answer is byte for byte the gRPC
# answer to the same request (Python's gRPC client, raw bytes), the JSON answer is the same
# message. The errors as Connect errors naming the field or the limit (bad JSON 400, too large
# 413, wrong content type 415, unknown method 404, a slow body 408), only the routes served,
# the security headers, no CORS unless configured, the --http_* flags refused when out of range.
# Usage: http_api_e2e_test.sh KOMA_SERVER PYTHON3 SAMPLES_DIR   (PYTHONPATH: the koma package)
set -euo pipefail
server_bin=$1 python=$2 samples=$3

source "$(dirname "$0")/lib.sh"
helper="$(dirname "$0")/http_api_requests.py"

check_refused '--http_port: 70000 must be in [-1, 65535]' "$server_bin" --http_port=70000
check_refused '--http_cors_origin: "https://a.example/x" is not an origin' "$server_bin" \
  --http_port=0 --http_cors_origin=https://a.example/x
check_refused '--http_max_body_bytes: 10 must be >= 1024' "$server_bin" --http_port=0 \
  --http_max_body_bytes=10
check_refused '--http_port_file needs --http_port' "$server_bin" --http_port_file="$work/x"

start_server "$server_bin" --http_port=0 --http_port_file="$work/http.port" \
  --http_max_body_bytes=2000000 --http_request_timeout_ms=1000
http_port=$(cat "$work/http.port")
[ "$http_port" -gt 0 ] || fail "the HTTP port file holds '$http_port'"
base="http://127.0.0.1:$http_port"
check_refused "--http_address/--http_port: could not listen on 127.0.0.1:$http_port" \
  "$server_bin" --http_port="$http_port"

# post RPC CONTENT_TYPE BODY_FILE OUT: the status code on stdout, the body to OUT, the
# headers to OUT.headers.
post() {
  curl -sS --max-time 60 -o "$4" -D "$4.headers" -w '%{http_code}' -X POST \
    -H "Content-Type: $2" --data-binary "@$3" "$base/koma.v1.Retime/$1"
}
# expect_status WANT GOT WHAT OUT
expect_status() {
  [ "$2" = "$1" ] || fail "$3: HTTP $2, want $1: $(head -c 400 "$4")"
}
# expect_connect_error OUT CODE FRAGMENT: OUT is a Connect error of CODE naming FRAGMENT.
expect_connect_error() {
  "$python" - "$@" <<'PY' || fail "$1: not the Connect error $2 naming '$3': $(head -c 400 "$1")"
import json, sys
error = json.load(open(sys.argv[1]))
sys.exit(0 if error['code'] == sys.argv[2] and sys.argv[3] in error['message'] else 1)
PY
}

"$python" "$helper" make "$samples" "$work"
for rpc in RetimeSkeletal RetimeCurves LipBlink; do
  "$python" "$helper" grpc "$target" "$rpc" "$work/$rpc.bin" "$work/$rpc.grpc"
  code=$(post "$rpc" application/proto "$work/$rpc.bin" "$work/$rpc.http.bin")
  expect_status 200 "$code" "$rpc binary" "$work/$rpc.http.bin"
  cmp -s "$work/$rpc.grpc" "$work/$rpc.http.bin" ||
    fail "$rpc: the binary answer differs from gRPC's ($(stat -c %s "$work/$rpc.grpc") vs $(stat -c %s "$work/$rpc.http.bin") bytes)"
  grep -qi '^Content-Type: application/proto' "$work/$rpc.http.bin.headers" ||
    fail "$rpc binary: $(cat "$work/$rpc.http.bin.headers")"
  code=$(post "$rpc" application/json "$work/$rpc.json" "$work/$rpc.http.json")
  expect_status 200 "$code" "$rpc JSON" "$work/$rpc.http.json"
  "$python" "$helper" same "$rpc" "$work/$rpc.http.json" "$work/$rpc.grpc" ||
    fail "$rpc: the JSON answer is not gRPC's"
  echo "$rpc: binary $(stat -c %s "$work/$rpc.grpc") bytes = gRPC's; JSON $(stat -c %s "$work/$rpc.http.json") bytes, the same message"
done

# Every response carries the security headers and no CORS header (none configured).
headers="$work/RetimeCurves.http.json.headers"
for header in "Content-Security-Policy: default-src 'none'" 'X-Content-Type-Options: nosniff' \
  'X-Frame-Options: DENY' 'Referrer-Policy: no-referrer'; do
  grep -qiF "$header" "$headers" || fail "no '$header': $(cat "$headers")"
done
grep -qi '^Access-Control-Allow-Origin' "$headers" && fail "CORS without --http_cors_origin"

# Bad JSON: 400 invalid_argument naming the field.
printf '{"motion3Json": 12}' >"$work/bad.json"
code=$(post RetimeCurves application/json "$work/bad.json" "$work/out")
expect_status 400 "$code" "bad JSON" "$work/out"
expect_connect_error "$work/out" invalid_argument motion3_json
# The service's own validation, as gRPC words it.
printf '{"curves": {"frameCount": 3}}' >"$work/invalid.json"
code=$(post RetimeCurves application/json "$work/invalid.json" "$work/out")
expect_status 400 "$code" "invalid request" "$work/out"
expect_connect_error "$work/out" invalid_argument 'curves.fps'
# Too large: 413 naming the limit, without the body being read.
head -c 3000000 /dev/zero >"$work/big.bin"
code=$(post LipBlink application/proto "$work/big.bin" "$work/out")
expect_status 413 "$code" "too large" "$work/out"
expect_connect_error "$work/out" resource_exhausted '--http_max_body_bytes=2000000'
# The same through chunked transfer (no Content-Length): cut at the limit.
code=$(curl -sS --max-time 60 -o "$work/out" -w '%{http_code}' -X POST \
  -H 'Content-Type: application/proto' -H 'Transfer-Encoding: chunked' \
  --data-binary @"$work/big.bin" "$base/koma.v1.Retime/LipBlink")
expect_status 413 "$code" "too large, chunked" "$work/out"
expect_connect_error "$work/out" resource_exhausted '--http_max_body_bytes=2000000'
# Wrong content type: 415 naming it.
code=$(post LipBlink text/plain "$work/LipBlink.json" "$work/out")
expect_status 415 "$code" "wrong content type" "$work/out"
expect_connect_error "$work/out" invalid_argument '"text/plain"'
# Unknown method: 404 not_found naming it; a path outside the API: 404; GET: 405.
code=$(post RetimeAll application/json "$work/LipBlink.json" "$work/out")
expect_status 404 "$code" "unknown method" "$work/out"
expect_connect_error "$work/out" not_found '/koma.v1.Retime/RetimeAll'
for path in /etc/passwd /../../../etc/passwd /%2e%2e/%2e%2e/etc/passwd /metrics; do
  code=$(curl -sS --path-as-is --max-time 10 -o "$work/out" -w '%{http_code}' "$base$path")
  [ "$code" = 404 ] || [ "$code" = 400 ] || fail "GET $path: HTTP $code: $(head -c 300 "$work/out")"
  grep -q 'root:' "$work/out" && fail "GET $path served a file"
done
code=$(curl -sS --max-time 10 -o "$work/out" -w '%{http_code}' "$base/koma.v1.Retime/LipBlink")
expect_status 405 "$code" "GET on an RPC" "$work/out"
# A client that sends a Content-Length and then stalls: 408 after --http_request_timeout_ms
# (1 s here), its thread freed, not held.
"$python" - "$http_port" <<'PY' || fail "a stalled body was not cut off with 408"
import socket, sys, time
s = socket.create_connection(('127.0.0.1', int(sys.argv[1])), timeout=10)
s.sendall(b'POST /koma.v1.Retime/LipBlink HTTP/1.1\r\nHost: x\r\n'
          b'Content-Type: application/proto\r\nContent-Length: 100\r\n\r\n0123456789')
start = time.monotonic()
answer = s.recv(4096)
seconds = time.monotonic() - start
print('stalled body: answered after %.2f s: %s' % (seconds, answer.split(b'\r\n')[0].decode()))
sys.exit(0 if answer.startswith(b'HTTP/1.1 408') and seconds < 5 else 1)
PY
# The server still answers both ports.
code=$(post LipBlink application/json "$work/LipBlink.json" "$work/out")
expect_status 200 "$code" "LipBlink after the errors" "$work/out"
"$python" "$helper" grpc "$target" LipBlink "$work/LipBlink.bin" "$work/again.grpc"
stop_server

# CORS only for the configured origin; --http_keep_alive_ms=0: one request per connection.
start_server "$server_bin" --http_port=0 --http_port_file="$work/http.port" \
  --http_cors_origin=https://tools.example.com --http_keep_alive_ms=0
base="http://127.0.0.1:$(cat "$work/http.port")"
preflight() {
  curl -sS --max-time 10 -o /dev/null -D - -X OPTIONS -H "Origin: $1" \
    -H 'Access-Control-Request-Method: POST' "$base/koma.v1.Retime/LipBlink"
}
preflight https://tools.example.com | grep -qi '^Access-Control-Allow-Origin: https://tools.example.com' ||
  fail "the configured origin got no CORS preflight answer"
preflight https://evil.example | grep -qi '^Access-Control-Allow-Origin' &&
  fail "another origin got CORS headers"
code=$(post LipBlink application/proto "$work/LipBlink.bin" "$work/out")
expect_status 200 "$code" "LipBlink without keep-alive" "$work/out"
grep -qi '^Connection: close' "$work/out.headers" ||
  fail "--http_keep_alive_ms=0 kept the connection: $(cat "$work/out.headers")"
stop_server
echo "http_api_e2e: PASS"

#!/usr/bin/env bash
# TLS and mutual TLS: a throwaway CA made with the openssl CLI signs the server's and a
# client's certificate; a second CA signs an impostor's. The real server requires client
# certificates; the real client succeeds with the right one and fails with none or the wrong
# one, and fails against TLS without trusting the CA. Usage: tls_e2e_test.sh KOMA_SERVER KOMA
set -euo pipefail
server_bin=$1 client_bin=$2
source "$(dirname "$0")/lib.sh"
pki=$work/pki
mkdir -p "$pki"

# make_ca NAME; make_cert NAME CA SUBJECT_ALT_NAMES
make_ca() {
  openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj "/CN=$1" \
    -keyout "$pki/$1.key" -out "$pki/$1.pem" 2>/dev/null
}
make_cert() {
  openssl req -newkey rsa:2048 -nodes -subj "/CN=$1" -keyout "$pki/$1.key" \
    -out "$pki/$1.csr" 2>/dev/null
  printf 'subjectAltName=%s\n' "$3" >"$pki/$1.ext"
  openssl x509 -req -in "$pki/$1.csr" -CA "$pki/$2.pem" -CAkey "$pki/$2.key" \
    -CAcreateserial -days 2 -extfile "$pki/$1.ext" -out "$pki/$1.pem" 2>/dev/null
}
make_ca koma-test-ca
make_ca impostor-ca
make_cert server koma-test-ca "IP:127.0.0.1,DNS:localhost"
make_cert client koma-test-ca "DNS:render-node-1"
make_cert impostor impostor-ca "DNS:render-node-1"

start_server "$server_bin" --tls_cert="$pki/server.pem" --tls_key="$pki/server.key" \
  --tls_client_ca="$pki/koma-test-ca.pem"

ca=(--tls-ca "$pki/koma-test-ca.pem")
[ "$("$client_bin" health --server "$target" "${ca[@]}" --tls-cert "$pki/client.pem" \
     --tls-key "$pki/client.key")" = SERVING ] || fail "mutual TLS with the right client certificate"
KOMA_TLS_CA=$pki/koma-test-ca.pem KOMA_TLS_CERT=$pki/client.pem KOMA_TLS_KEY=$pki/client.key \
  "$client_bin" skeletal "$(dirname "$0")/../../samples/pitch.bvh" -o "$work/out.bvh" \
  --server "$target" >/dev/null || fail "retiming over mutual TLS (files from the environment)"
"$client_bin" live --input "$(dirname "$0")/../../samples/voice.flac" --speed 0 --json -q \
  --server "$target" "${ca[@]}" --tls-cert "$pki/client.pem" --tls-key "$pki/client.key" \
  >"$work/live.jsonl" || fail "koma live over mutual TLS"
[ "$(wc -l <"$work/live.jsonl")" = 92 ] || fail "koma live over mutual TLS: not 92 frames"

refused() {  # the command must fail with UNAVAILABLE
  local code=0
  "$@" --server "$target" --deadline 5 >/dev/null 2>"$work/err.txt" || code=$?
  [ "$code" = 1 ] && grep -q "UNAVAILABLE" "$work/err.txt"
}
refused "$client_bin" health "${ca[@]}" || fail "no client certificate was accepted"
refused "$client_bin" health "${ca[@]}" --tls-cert "$pki/impostor.pem" \
  --tls-key "$pki/impostor.key" || fail "a client certificate from another CA was accepted"
refused "$client_bin" health || fail "a plaintext client was accepted"
refused "$client_bin" live --input "$(dirname "$0")/../../samples/voice.flac" --speed 0 \
  "${ca[@]}" || fail "koma live without a client certificate was accepted"
refused "$client_bin" health --tls-cert "$pki/client.pem" --tls-key "$pki/client.key" \
  || fail "the client trusted a server certificate from an unknown CA"

stop_server
echo "PASS: TLS and mutual TLS"

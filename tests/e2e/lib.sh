# shellcheck shell=bash
# Shared by the end-to-end scripts and bench/load_matrix.sh and bench/load_pairs.sh (sourced,
# not run). Gives each a scratch directory `$work`, a `fail` that prints the server log, and
# a server (koma_server, or any with --address and --port_file) on a free loopback port,
# killed on any exit.
#   start_server SERVER [FLAGS...]        sets $server_pid and $target (127.0.0.1:PORT)
#   stop_server                           SIGTERM, and fails unless the server exits 0

work=$(mktemp -d)
server_pid=""
cleanup() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then kill -KILL "$server_pid"; fi
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  echo "--- server log" >&2
  cat "$work/server.log" >&2 || true
  exit 1
}

start_server() {
  local server_bin=$1
  shift
  rm -f "$work/port"  # a previous server's, when a script starts several in turn
  "$server_bin" --address=127.0.0.1:0 --port_file="$work/port" "$@" 2>"$work/server.log" &
  server_pid=$!
  for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
  [ -s "$work/port" ] || fail "server did not write its port within 10 s"
  # shellcheck disable=SC2034  # read by the scripts that source this file
  target="127.0.0.1:$(cat "$work/port")"
}

stop_server() {
  kill -TERM "$server_pid"
  local code=0
  wait "$server_pid" || code=$?
  server_pid=""
  [ "$code" = 0 ] || fail "server exited $code after SIGTERM"
}

# check_refused MESSAGE SERVER FLAGS...: the server must refuse to start: exit 1 within 10 s
# with MESSAGE (a fixed string) on stderr. Environment variables set for the call reach it.
check_refused() {
  local want=$1 server_bin=$2
  shift 2
  local code=0
  timeout 10 "$server_bin" --address=127.0.0.1:0 "$@" 2>"$work/refused.txt" || code=$?
  [ "$code" = 1 ] || fail "koma_server $* exited $code, want 1: $(cat "$work/refused.txt")"
  grep -qF -- "$want" "$work/refused.txt" || fail "koma_server $*: $(cat "$work/refused.txt")"
}

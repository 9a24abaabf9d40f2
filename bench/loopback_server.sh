# shellcheck shell=bash
# Shared by bench/load_matrix.sh and bench/load_pairs.sh (sourced, not run): one server at a
# time on a free loopback port, in a scratch directory `$work` that goes on exit, and the
# server killed on any exit, failed or not.
#   start BINARY [FLAGS...]   sets $pid and $port (the server's stderr: $work/server.log)
#   stop                      SIGTERM, and fails unless the server exits 0
#   peak                      the server's peak RSS so far (VmHWM), MiB

work=$(mktemp -d)
pid=""
cleanup() {
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid"; fi
  rm -rf "$work"
}
trap cleanup EXIT

start() {
  rm -f "$work/port"
  "$@" --address=127.0.0.1:0 --port_file="$work/port" 2>>"$work/server.log" &
  pid=$!
  for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
  [ -s "$work/port" ] || { echo "server did not start: $*" >&2; cat "$work/server.log" >&2; exit 1; }
  # shellcheck disable=SC2034  # read by the scripts that source this file
  port=$(cat "$work/port")
}

peak() { awk '/VmHWM/ { printf "%.0f", $2 / 1024 }' "/proc/$pid/status"; }

stop() {
  kill -TERM "$pid"
  wait "$pid" || { echo "server exited $? after SIGTERM" >&2; exit 1; }
  pid=""
}

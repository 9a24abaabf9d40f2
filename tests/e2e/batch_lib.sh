# shellcheck shell=bash
# Shared by the `koma batch` end-to-end scripts (sourced after lib.sh): named koma_servers on
# loopback, each with its own log, port file and Prometheus endpoint, all killed on exit.
#   start_named NAME [FLAGS...]   starts server NAME (on $port_NAME if set, else a free port);
#                                 sets pid_NAME, port_NAME, target_NAME
#   stop_named NAME               SIGTERM, and fails unless the server exits 0
#   rpcs_started NAME             calls the server has started (sum of grpc_server_started_total)
# Needs $server_bin and $python (Debian's python3).

named_pids=()
batch_cleanup() {
  for pid in "${named_pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  cleanup
}
trap batch_cleanup EXIT

start_named() {
  local name=$1
  shift
  local port_var="port_$name"
  local port=${!port_var:-0}
  rm -f "$work/$name.port" "$work/$name.mport"
  "$server_bin" --address="127.0.0.1:$port" --port_file="$work/$name.port" \
    --metrics_address=127.0.0.1:0 --metrics_port_file="$work/$name.mport" --log_level=warn \
    "$@" 2>>"$work/$name.log" &
  local pid=$!
  named_pids+=("$pid")
  for _ in $(seq 100); do [ -s "$work/$name.port" ] && break; sleep 0.1; done
  [ -s "$work/$name.port" ] || { cat "$work/$name.log" >&2; fail "server $name did not start"; }
  printf -v "pid_$name" '%s' "$pid"
  printf -v "port_$name" '%s' "$(cat "$work/$name.port")"
  printf -v "target_$name" '127.0.0.1:%s' "$(cat "$work/$name.port")"
}

stop_named() {
  local pid_var="pid_$1"
  kill -TERM "${!pid_var}"
  local code=0
  wait "${!pid_var}" || code=$?
  [ "$code" = 0 ] || { cat "$work/$1.log" >&2; fail "server $1 exited $code after SIGTERM"; }
}

rpcs_started() {
  "$python" - "$(cat "$work/$1.mport")" <<'PY'
import sys, urllib.request
text = urllib.request.urlopen(f"http://127.0.0.1:{sys.argv[1]}/metrics", timeout=10).read().decode()
print(int(sum(float(line.split()[-1]) for line in text.splitlines()
              if line.startswith("grpc_server_started_total{"))))
PY
}

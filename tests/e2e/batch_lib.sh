# shellcheck shell=bash
# Shared by the `koma batch` end-to-end scripts (sourced; it sources lib.sh): named koma_servers
# on loopback, each with its own log, port file and Prometheus endpoint (lib.sh's
# start_server_as), all killed on exit.
#   start_named NAME [FLAGS...]   starts server NAME (on $on_port if set, else a free port);
#                                 sets pid_NAME, port_NAME, target_NAME
#   rpcs_started NAME             calls the server has started (sum of grpc_server_started_total)
#   summary_field FILE KEY        a field of a `koma batch --summary` file
# Needs $server_bin.

# shellcheck source=lib.sh
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

start_named() {
  local name=$1
  shift
  start_server_as "$name" "$server_bin" --metrics_address=127.0.0.1:0 \
    --metrics_port_file="$work/$name.mport" --log_level=warn "$@"
}

summary_field() {
  /usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$@"
}

rpcs_started() { printf '%.0f\n' "$(metric_sum "$1" grpc_server_started_total)"; }

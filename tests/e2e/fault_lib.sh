# shellcheck shell=bash
# Shared by the fault tests (sourced; it sources lib.sh): the server's memory and metrics,
# koma_load's report, and the checks every fault test ends with. Start the server with
#   start_server SERVER ... "${with_metrics[@]}"
#   rss_mib PID / peak_rss_mib PID    VmRSS / VmHWM (peak) of a process, MiB
#   wait_rss_at_most PID MIB SECONDS  polls until RSS <= MIB; fails after SECONDS
#   metric NAME                       the server's series NAME (its Prometheus endpoint)
#   report FILE KEY                   a field of koma_load's JSON report (errors.CODE for one code)
#   check_released WHEN               within 10 s no call is in flight; then the memory budget
#                                     holds nothing
#   check_still_serves WHEN LOAD PITCH  three small calls (koma_load LOAD on PITCH) succeed

# shellcheck source=lib.sh
. "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

fail_log_lines=20  # a flood logs hundreds of calls
# shellcheck disable=SC2034  # used by the scripts that source this file
with_metrics=(--metrics_address=127.0.0.1:0 --metrics_port_file="$work/server.mport")

rss_mib() { awk '/^VmRSS:/ {printf "%d", $2 / 1024}' "/proc/$1/status"; }
peak_rss_mib() { awk '/^VmHWM:/ {printf "%d", $2 / 1024}' "/proc/$1/status"; }
rss_at_most() { [ "$(rss_mib "$1")" -le "$2" ]; }
rss_above() { [ "$(rss_mib "$1")" -gt "$2" ]; }

wait_rss_at_most() {
  wait_until "$3" rss_at_most "$1" "$2" ||
    fail "server RSS $(rss_mib "$1") MiB still above $2 MiB after $3 s"
}

metric() { metric_sum server "$1"; }
metric_is() { [ "$(metric "$1")" = "$2" ]; }

report() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
value = json.load(open(sys.argv[1]))
for key in sys.argv[2].split("."):
    value = value.get(key, 0) if isinstance(value, dict) else 0
print(value)
PY
}

check_released() {
  wait_until 10 metric_is koma_requests_in_flight 0.0 ||
    fail "calls still in flight 10 s $1"
  metric_is koma_memory_budget_in_use_bytes 0.0 ||
    fail "the memory budget still holds $(metric koma_memory_budget_in_use_bytes) bytes $1"
}

check_still_serves() {
  "$2" --rpc skeletal --input "$3" --count 3 --server "$target" --fail-on-error --quiet \
    >"$work/after.out" 2>&1 || fail "a call $1 failed: $(cat "$work/after.out")"
}

# shellcheck shell=bash
# Shared by the fault tests (sourced after lib.sh): the server's memory and metrics, and
# koma_load's report.
#   rss_mib PID / peak_rss_mib PID    VmRSS / VmHWM (peak) of a process, MiB
#   metric NAME                       a series' value from $metrics_target's /metrics
#   report FILE KEY                   a field of koma_load's JSON report (errors.CODE for one code)
#   wait_rss_at_most PID MIB SECONDS  polls until RSS <= MIB; fails after SECONDS

# lib.sh's fail, with the server log's last lines only (a flood logs hundreds of calls).
fail() {
  echo "FAIL: $*" >&2
  echo "--- server log (last 20 lines)" >&2
  tail -n 20 "$work/server.log" >&2 || true
  exit 1
}

rss_mib() { awk '/^VmRSS:/ {printf "%d", $2 / 1024}' "/proc/$1/status"; }
peak_rss_mib() { awk '/^VmHWM:/ {printf "%d", $2 / 1024}' "/proc/$1/status"; }

# The server's metrics endpoint: start_server with --metrics_address=127.0.0.1:0
# --metrics_port_file="$work/metrics_port", then call this.
metrics_target=""
find_metrics() {
  for _ in $(seq 50); do [ -s "$work/metrics_port" ] && break; sleep 0.1; done
  [ -s "$work/metrics_port" ] || fail "server did not write its metrics port"
  metrics_target="127.0.0.1:$(cat "$work/metrics_port")"
}

metric() {
  /usr/bin/python3 - "$metrics_target" "$1" <<'PY'
import sys, urllib.request
target, name = sys.argv[1:]
text = urllib.request.urlopen("http://%s/metrics" % target, timeout=10).read().decode()
for line in text.splitlines():
    if line.startswith(name + " ") or line.startswith(name + "{}"):
        print(float(line.split()[-1]))
        sys.exit(0)
sys.exit("metric %s not found" % name)
PY
}

report() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
value = json.load(open(sys.argv[1]))
for key in sys.argv[2].split("."):
    value = value.get(key, 0) if isinstance(value, dict) else 0
print(value)
PY
}

wait_rss_at_most() {
  local pid=$1 mib=$2 seconds=$3
  for _ in $(seq $((seconds * 10))); do
    [ "$(rss_mib "$pid")" -le "$mib" ] && return 0
    sleep 0.1
  done
  fail "server RSS $(rss_mib "$pid") MiB still above $mib MiB after $seconds s"
}

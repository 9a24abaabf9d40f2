# shellcheck shell=bash
# Shared by the end-to-end and fault scripts (fault_lib.sh and batch_lib.sh build on it),
# tests/report, tests/python and bench/ (sourced, not run): one place for a scratch directory,
# servers on loopback, bounded waits and failures.
#   $work                                 a scratch directory, removed on exit
#   fail MESSAGE                          the last $fail_log_lines lines of every $work/*.log,
#                                         then MESSAGE; exits 1
#   start_server SERVER [FLAGS...]        koma_server (or any with --address and --port_file) on
#                                         a free loopback port: sets $server_pid and $target
#                                         (127.0.0.1:PORT); its log is $work/server.log
#   stop_server                           SIGTERM; fails unless it exits 0 within 30 s
#   start_server_as NAME SERVER [FLAGS...]  one of several servers: log $work/NAME.log (appended
#                                         to, so a restarted server's log follows its first),
#                                         port on $on_port if set (a restart), else a free one;
#                                         sets pid_NAME, port_NAME, target_NAME
#   stop_server_as NAME [SECONDS]         SIGTERM; fails unless it exits 0 within SECONDS (30);
#                                         sets $stopped_ms
#   kill_server_as NAME                   SIGKILL (no drain), and waits for it
#   pids_to_kill                          an array: every server started here, and whatever a
#                                         script adds, is killed with SIGKILL on any exit
#   reap PID                              waits for PID (started here) and returns its exit
#                                         status; PID leaves pids_to_kill
#   wait_until SECONDS COMMAND...         runs COMMAND every $poll_interval s (0.1) until it
#                                         succeeds; returns 1 if it has not after SECONDS
#   expect_exit CODE ERR_FILE COMMAND...  runs COMMAND (at most 120 s), stderr to ERR_FILE;
#                                         fails unless it exits CODE
#   expect_error CODE PATTERN COMMAND...  the same, stderr to $work/err.txt, and fails unless
#                                         it holds PATTERN (a grep regular expression)
#   check_refused MESSAGE SERVER FLAGS... the server must refuse to start (below)
#   free_port                             a free loopback TCP port (bound and released)
#   metric_sum NAME SERIES                the sum of SERIES (all its labels) on the Prometheus
#                                         endpoint of server NAME, started with
#                                         --metrics_address=127.0.0.1:0
#                                         --metrics_port_file="$work/NAME.mport"
#   answered_ok LOG                       RetimeSkeletal calls answered OK in a JSON server log
#   both_answered N                       servers a and b (JSON logs) have each answered N

work=$(mktemp -d)
pids_to_kill=()
server_pid=""
fail_log_lines=100
poll_interval=0.1

cleanup() {
  local pid
  for pid in "${pids_to_kill[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
  rm -rf "$work"
  return 0
}
trap cleanup EXIT

fail() {
  local log
  for log in "$work"/*.log; do
    [ -f "$log" ] || continue
    echo "--- $log (last $fail_log_lines lines)" >&2
    tail -n "$fail_log_lines" "$log" >&2
  done
  echo "FAIL: $*" >&2
  exit 1
}

wait_until() {
  local seconds=$1
  shift
  local deadline_ns=$(($(date +%s%N) + seconds * 1000000000))
  until "$@"; do
    [ "$(date +%s%N)" -lt "$deadline_ns" ] || return 1
    sleep "$poll_interval"
  done
}

running() { kill -0 "$1" 2>/dev/null; }
not_running() { ! kill -0 "$1" 2>/dev/null; }

# forget_pid PID: a process that has been waited for is no longer killed on exit (its number
# may belong to another process by then).
forget_pid() {
  local kept=() pid
  for pid in "${pids_to_kill[@]}"; do [ "$pid" = "$1" ] || kept+=("$pid"); done
  pids_to_kill=("${kept[@]}")
}

reap() {
  local code=0
  wait "$1" || code=$?
  forget_pid "$1"
  return "$code"
}

start_server_as() {
  local name=$1 bin=$2
  shift 2
  rm -f "$work/$name.port"
  "$bin" --address="127.0.0.1:${on_port:-0}" --port_file="$work/$name.port" "$@" \
    2>>"$work/$name.log" &
  local pid=$!
  pids_to_kill+=("$pid")
  wait_until 10 test -s "$work/$name.port" ||
    fail "server $name did not write its port within 10 s"
  local port
  port=$(cat "$work/$name.port")
  printf -v "pid_$name" '%s' "$pid"
  printf -v "port_$name" '%s' "$port"
  printf -v "target_$name" '127.0.0.1:%s' "$port"
}

stop_server_as() {
  local name=$1 seconds=${2:-30} pid_var="pid_$1"
  local pid=${!pid_var} start_ns code=0
  start_ns=$(date +%s%N)
  kill -TERM "$pid"
  wait_until "$seconds" not_running "$pid" ||
    fail "server $name still runs $seconds s after SIGTERM"
  reap "$pid" || code=$?
  [ "$code" = 0 ] || fail "server $name exited $code after SIGTERM"
  # shellcheck disable=SC2034  # read by the scripts that source this file
  stopped_ms=$((($(date +%s%N) - start_ns) / 1000000))
}

kill_server_as() {
  local pid_var="pid_$1"
  kill -KILL "${!pid_var}"
  reap "${!pid_var}" 2>/dev/null || true
}

start_server() {
  start_server_as server "$@"
  # shellcheck disable=SC2154  # set by start_server_as
  server_pid=$pid_server
  # shellcheck disable=SC2034,SC2154  # read by the scripts that source this file
  target=$target_server
}

stop_server() {
  stop_server_as server
  # shellcheck disable=SC2034  # read by the scripts that source this file
  server_pid=""
}

expect_exit() {
  local want=$1 err=$2
  shift 2
  local code=0
  timeout 120 "$@" 2>"$err" || code=$?
  [ "$code" = "$want" ] || fail "$* exited $code, want $want: $(cat "$err")"
}

expect_error() {
  local want=$1 pattern=$2
  shift 2
  expect_exit "$want" "$work/err.txt" "$@"
  grep -q -- "$pattern" "$work/err.txt" ||
    fail "$*: stderr lacks \"$pattern\": $(cat "$work/err.txt")"
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

free_port() {
  /usr/bin/python3 -c \
    'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

metric_sum() {
  wait_until 5 test -s "$work/$1.mport" || fail "server $1 did not write its metrics port"
  /usr/bin/python3 - "$(cat "$work/$1.mport")" "$2" <<'PY'
import sys, urllib.request
port, name = sys.argv[1:]
text = urllib.request.urlopen("http://127.0.0.1:%s/metrics" % port, timeout=10).read().decode()
values = [float(line.split()[-1]) for line in text.splitlines()
          if line.startswith(name + " ") or line.startswith(name + "{")]
if not values:
    sys.exit("metric %s not found" % name)
print(sum(values))
PY
}

answered_ok() { grep -c '"code":"OK".*"method":"RetimeSkeletal"' "$1" || true; }
both_answered() {
  [ "$(answered_ok "$work/a.log")" -ge "$1" ] && [ "$(answered_ok "$work/b.log")" -ge "$1" ]
}

#!/usr/bin/env bash
# e2e.scale_out: two real koma_server backends on loopback take load while one of them is
# stopped with SIGTERM, and no call may fail.
#   Part 1: koma_load -> nginx (deploy/nginx/koma.conf itself, its addresses substituted)
#           -> backends a and b.
#   Part 2: koma_load --server a,b (the client balances with round_robin, no proxy), fresh
#           backends.
# Each part: 4 s of closed-loop load (concurrency 4, samples/pitch.bvh, no warmup, so every
# call counts); about 1 s in, once both backends have answered calls, backend a gets
# SIGTERM. Checks: koma_load reports every call OK, a exits 0 (and b at the end), both
# backends answered calls before the SIGTERM and b after it (their JSON logs). Prints the
# calls per backend.
#   scale_out_test.sh KOMA_SERVER KOMA_LOAD KOMA NGINX_CONF PITCH_BVH
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_server_as
set -euo pipefail
server_bin=$1
load_bin=$2
koma_bin=$3
nginx_conf=$4
pitch=$5

# shellcheck source=lib.sh
source "$(dirname "$0")/lib.sh"
fail_log_lines=10
nginx_pid=""  # the nginx master; its workers are its children
# nginx first, gracefully: its workers outlive a master killed with SIGKILL.
stop_nginx_on_exit() {
  if [ -n "$nginx_pid" ] && running "$nginx_pid"; then
    local workers
    workers=$(pgrep -P "$nginx_pid" || true)
    kill -TERM "$nginx_pid" 2>/dev/null || true
    wait_until 5 not_running "$nginx_pid" || true
    for pid in $workers; do kill -KILL "$pid" 2>/dev/null || true; done
  fi
}
trap 'stop_nginx_on_exit; cleanup' EXIT

# stop_backend NAME: SIGTERM; fails unless it exits 0 within 15 s (its --shutdown_delay_ms
# of 1 s plus --shutdown_grace_ms of 10 s, with room).
stop_backend() {
  stop_server_as "$1" 15
  echo "backend $1 exited 0 $stopped_ms ms after SIGTERM"
}

# check_part LABEL [NGINX_PORT]: koma_load's report has every call OK; a answered calls before its
# SIGTERM, b before and after it (by the logs' ISO 8601 UTC timestamps, which sort as
# text). Prints the calls per backend from the logs and as koma_load saw them.
check_part() {
  python3 - "$1" "$work/$1.json" "$work/a.log" "$work/b.log" "$port_a" "$port_b" "${2:-}" <<'PY'
import json, sys
label, report_path, a_log, b_log, a_port, b_port, nginx_port = sys.argv[1:]

def entries(path):
    for line in open(path):
        try:
            yield json.loads(line)
        except ValueError:
            pass

def answered(path):  # timestamps of the RetimeSkeletal calls answered OK
    return [e["ts"] for e in entries(path)
            if e.get("method") == "RetimeSkeletal" and e.get("code") == "OK"]

sigterm = [e["ts"] for e in entries(a_log) if e.get("msg", "").startswith("received SIGTERM")]
r = json.load(open(report_path))
problems = []
if r["count"] == 0:
    problems.append("koma_load made no calls")
if r["errors"] or r["ok"] != r["count"]:
    problems.append("koma_load: %d of %d calls OK, errors %s" % (r["ok"], r["count"], r["errors"]))
if not sigterm:
    problems.append("backend a logged no SIGTERM")
a, b = answered(a_log), answered(b_log)
when = sigterm[0] if sigterm else ""
a_before = sum(ts < when for ts in a)
b_before = sum(ts < when for ts in b)
b_after = len(b) - b_before
if a_before == 0:
    problems.append("backend a answered no call before its SIGTERM")
if b_before == 0 or b_after == 0:
    problems.append("backend b answered %d calls before a's SIGTERM, %d after"
                    % (b_before, b_after))
names = {"ipv4:127.0.0.1:" + a_port: "A", "ipv4:127.0.0.1:" + b_port: "B",
         "ipv4:127.0.0.1:" + nginx_port: "nginx"}
seen = ", ".join(sorted("%s=%d" % (names.get(peer, peer), n)
                        for peer, n in r.get("ok_by_peer", {}).items()))
print("%s: %d calls, %d OK, errors %s, %.0f calls/s" % (label, r["count"], r["ok"], r["errors"],
                                                        r["rps"]))
print("%s: calls per backend: A=%d, B=%d (A before its SIGTERM %d, after %d; B before %d, "
      "after %d; koma_load saw %s)" % (label, len(a), len(b), a_before, len(a) - a_before,
                                       b_before, b_after, seen))
if problems:
    print("FAIL: " + "; ".join(problems))
    sys.exit(1)
PY
}

# run_part LABEL TARGET [NGINX_PORT]: the load, SIGTERM to backend a mid-run, the checks.
run_part() {
  local label=$1 target=$2 nginx_port=${3:-}
  "$load_bin" --rpc skeletal --input "$pitch" --concurrency 4 --duration 4 --count 50000 \
    --max-duration 20 --deadline 10 --server "$target" --json "$work/$label.json" --quiet \
    >"$work/$label-load.log" 2>&1 &
  local load_pid=$!
  pids_to_kill+=("$load_pid")

  # About 1 s in, and once both backends have answered calls, stop backend a.
  sleep 1
  wait_until 5 both_answered 5 || true
  running "$load_pid" || fail "$label: koma_load ended before the SIGTERM"
  stop_backend a

  local code=0
  reap "$load_pid" || code=$?
  [ "$code" = 0 ] || fail "$label: koma_load exited $code: $(cat "$work/$label-load.log")"
  check_part "$label" "$nginx_port" >"$work/$label-check.out" ||
    fail "$(cat "$work/$label-check.out")"
  cat "$work/$label-check.out"
  stop_backend b
  mv "$work/a.log" "$work/$label-a.log"
  mv "$work/b.log" "$work/$label-b.log"
}

# --- Part 1: nginx with the shipped deploy/nginx/koma.conf in front of a and b.
command -v nginx >/dev/null || fail "nginx is not installed (scripts/install-deps.sh installs it)"
start_server_as a "$server_bin" --log_format=json
start_server_as b "$server_bin" --log_format=json
prefix="$work/nginx"
mkdir -p "$prefix/logs" "$prefix/temp"
nginx_port=$(free_port)
# The shipped file with only its three addresses changed; each must have been there.
sed -e "s/server 127\.0\.0\.1:50051;/server 127.0.0.1:$port_a;/" \
    -e "s/server 127\.0\.0\.1:50052;/server 127.0.0.1:$port_b;/" \
    -e "s/listen 127\.0\.0\.1:8080 /listen 127.0.0.1:$nginx_port /" \
    "$nginx_conf" >"$prefix/koma.conf"
[ "$(diff "$nginx_conf" "$prefix/koma.conf" | grep -c '^>')" = 3 ] ||
  fail "$nginx_conf no longer has the three addresses this test substitutes" \
       "(server 127.0.0.1:50051; server 127.0.0.1:50052; listen 127.0.0.1:8080)"
# A minimal main config around it: everything nginx writes stays in $prefix. As root, the
# workers run as root too (the default, nobody, could not write the temp dirs in $work).
# The access log records, per call, every backend tried and the gRPC status.
{
  if [ "$(id -u)" = 0 ]; then echo "user root;"; fi
  cat <<EOF
worker_processes 1;
pid $prefix/nginx.pid;
error_log $work/nginx-error.log notice;
events { worker_connections 256; }
http {
    log_format koma '\$status|\$upstream_addr|\$upstream_status|\$sent_trailer_grpc_status|'
                    '\$upstream_http_grpc_status|\$request_uri';
    access_log $prefix/logs/access.log koma;
    client_body_temp_path $prefix/temp/client_body;
    proxy_temp_path $prefix/temp/proxy;
    fastcgi_temp_path $prefix/temp/fastcgi;
    uwsgi_temp_path $prefix/temp/uwsgi;
    scgi_temp_path $prefix/temp/scgi;
    include $prefix/koma.conf;
}
EOF
} >"$prefix/nginx.conf"
nginx_args=(-p "$prefix" -e "$work/nginx-error.log" -c "$prefix/nginx.conf")
nginx -t "${nginx_args[@]}" >"$work/nginx-t.out" 2>&1 ||
  fail "nginx -t rejects $nginx_conf: $(cat "$work/nginx-t.out")"
echo "nginx -t: $nginx_conf (in a minimal main config) is valid"
nginx "${nginx_args[@]}" -g 'daemon off;' >"$work/nginx.log" 2>&1 &
nginx_pid=$!
pids_to_kill+=("$nginx_pid")
# Ready when the health service answers SERVING through it.
for _ in $(seq 50); do
  "$koma_bin" health --server "127.0.0.1:$nginx_port" --deadline 1 >/dev/null 2>&1 && break
  running "$nginx_pid" || fail "nginx exited at start"
  sleep 0.1
done
"$koma_bin" health --server "127.0.0.1:$nginx_port" --deadline 2 >/dev/null ||
  fail "health through nginx on 127.0.0.1:$nginx_port is not SERVING"
run_part nginx "127.0.0.1:$nginx_port" "$nginx_port"
kill -QUIT "$nginx_pid"  # graceful stop
code=0
reap "$nginx_pid" || code=$?
[ "$code" = 0 ] || fail "nginx exited $code"
nginx_pid=""
# What nginx saw: calls it moved to the other backend before sending them, and calls a
# backend failed as it shut down (the client retried those: koma_load reported them OK).
python3 - "$prefix/logs/access.log" <<'PY'
import sys
calls = moved = failed = 0
for line in open(sys.argv[1]):
    status, addrs, _, trailer_status, header_status, uri = line.rstrip("\n").split("|")
    if not uri.startswith("/koma.v1.Retime/"):
        continue
    calls += 1
    moved += "," in addrs
    failed += not (status == "200" and trailer_status == "0")
print("nginx: %d calls; %d moved to the other backend by nginx (connection refused); "
      "%d failed by a backend as it shut down and retried by the client" % (calls, moved, failed))
PY

# --- Part 2: no proxy; the client balances over fresh a and b.
start_server_as a "$server_bin" --log_format=json
start_server_as b "$server_bin" --log_format=json
run_part round_robin "$target_a,$target_b"
echo "PASS"

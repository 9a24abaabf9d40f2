#!/usr/bin/env bash
# End to end: `koma batch` through faults, against two real koma_servers on loopback.
# 1. 1,000 Pitch-size clips (and 2 bad ones); server a is SIGKILLed mid-batch and restarted on
#    its port: the batch finishes, every good clip is written exactly once (its own --verbose
#    log, the summary) and whole (equal to the single command's output), no temporary file is
#    left, the calls the kill failed were retried.
# 2. SIGINT mid-batch: exit 130, only whole outputs, the summary lists the rest as not done;
#    the rerun sends exactly one call per clip not done (the servers' metrics) and exits 0.
# Usage: batch_fault_e2e_test.sh KOMA_SERVER KOMA PYTHON3 PITCH_BVH
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_named
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 pitch=$4
here=$(cd "$(dirname "$0")" && pwd)

# shellcheck source=batch_lib.sh
source "$here/batch_lib.sh"  # and lib.sh

clips=1000
mkdir -p "$work/clips/x" "$work/clips/y"
for i in $(seq "$clips"); do cp "$pitch" "$work/clips/$([ $((i % 2)) = 0 ] && echo x || echo y)/pitch_$i.bvh"; done
echo "not a BVH" >"$work/clips/x/bad_1.bvh"
head -c 30000 "$pitch" >"$work/clips/y/bad_2.bvh"  # cut in the middle of the motion
start_named a --worker_threads=1
start_named b --worker_threads=1
"$client_bin" skeletal "$pitch" -o "$work/reference.bvh" --timing "$work/reference.csv" \
  --server "$target_b" >/dev/null || fail "the single command failed"

# written_count LOG: clips the batch has reported written so far.
written_count() { grep -c "^koma: wrote " "$1" 2>/dev/null || true; }
# wait_written LOG N PID: until N clips are written (at most 30 s); fails if PID ended first.
wait_written() {
  for _ in $(seq 3000); do
    [ "$(written_count "$1")" -ge "$2" ] && return 0
    kill -0 "$3" 2>/dev/null || fail "the batch ended before $2 clips were written: $(tail -3 "$1")"
    sleep 0.01
  done
  fail "fewer than $2 clips written in 30 s"
}
# check_outputs OUT SUMMARY: every finished clip's outputs (ok or up to date) equal the
# reference; no other file.
check_outputs() {
  "$python" - "$1" "$2" "$work/reference.bvh" "$work/reference.csv" <<'PY' || fail "outputs in $1"
import json, os, sys
out, summary, ref_bvh, ref_csv = sys.argv[1:]
want = {".bvh": open(ref_bvh, "rb").read(), ".csv": open(ref_csv, "rb").read()}
finished = [f for f in json.load(open(summary))["files"] if f["status"] in ("ok", "up_to_date")]
ok = {f["output"] for f in finished}
ok_timing = {f["timing"] for f in finished}
found = set()
for folder, _, names in os.walk(out):
    for name in names:
        path = os.path.join(folder, name)
        if name == ".koma-batch.json":
            continue
        if path not in ok and path not in ok_timing:
            sys.exit(f"{path}: not an output of a finished clip (partial or temporary?)")
        if open(path, "rb").read() != want[os.path.splitext(name)[1]]:
            sys.exit(f"{path}: differs from the single command's output")
        found.add(path)
missing = (ok | ok_timing) - found
if missing:
    sys.exit(f"{len(missing)} outputs of finished clips missing, e.g. {sorted(missing)[0]}")
print(f"{out}: {len(ok)} outputs and {len(ok_timing)} timing sheets whole and as the single command's")
PY
}

# 1. SIGKILL and restart of server a mid-batch.
"$client_bin" batch skeletal "$work/clips" -o "$work/out" --server "$target_a,$target_b" \
  --jobs 4 --timing --verbose --summary "$work/fault.json" 2>"$work/fault.err" &
batch_pid=$!
wait_written "$work/fault.err" 100 "$batch_pid"
calls_a=$(rpcs_started a)
kill_server_as a
kill -0 "$batch_pid" 2>/dev/null || fail "the batch finished before the kill: make it longer"
killed_at=$(written_count "$work/fault.err")
sleep 0.3
on_port=$port_a start_named a --worker_threads=1
running_at_restart=no
kill -0 "$batch_pid" 2>/dev/null && running_at_restart=yes
code=0
timeout 120 tail --pid="$batch_pid" -f /dev/null || fail "the batch did not finish within 120 s"
wait "$batch_pid" || code=$?
[ "$code" = 1 ] || fail "batch exited $code, want 1 (two bad clips): $(tail -5 "$work/fault.err")"
grep -q "^koma batch: 1002 clips: 1000 done, 0 up to date, 2 failed, 0 not done" "$work/fault.err" \
  || fail "summary line: $(tail -3 "$work/fault.err")"
[ "$calls_a" -gt 0 ] || fail "server a had no call before it was killed"
retried=$(summary_field "$work/fault.json" retried)
[ "$retried" -ge 1 ] || fail "no call was retried after the kill"
# Each output written once: 1000 "wrote" lines, 1000 distinct paths.
[ "$(written_count "$work/fault.err")" = 1000 ] || fail "$(written_count "$work/fault.err") writes"
[ "$(grep "^koma: wrote " "$work/fault.err" | cut -d' ' -f3 | sort -u | wc -l)" = 1000 ] \
  || fail "an output was written twice"
check_outputs "$work/out" "$work/fault.json"
echo "fault: server a killed after $killed_at clips ($calls_a calls on it), restarted" \
  "(batch still running: $running_at_restart); $retried calls retried; 1000 written once each"

# 2. SIGINT mid-batch, then the rerun finishes the rest.
"$client_bin" batch skeletal "$work/clips" -o "$work/out2" --server "$target_a,$target_b" \
  --jobs 4 --timing --verbose --summary "$work/int.json" 2>"$work/int.err" &
batch_pid=$!
wait_written "$work/int.err" 100 "$batch_pid"
kill -INT "$batch_pid"
code=0
timeout 60 tail --pid="$batch_pid" -f /dev/null || fail "the batch did not stop within 60 s"
wait "$batch_pid" || code=$?
[ "$code" = 130 ] || fail "after SIGINT the batch exited $code, want 130: $(tail -3 "$work/int.err")"
[ "$(summary_field "$work/int.json" interrupted)" = True ] || fail "summary: not interrupted"
ok=$(summary_field "$work/int.json" ok)
not_done=$(summary_field "$work/int.json" not_done)
failed=$(summary_field "$work/int.json" failed)
[ "$not_done" -gt 0 ] || fail "SIGINT left nothing to do"
[ $((ok + not_done + failed)) = 1002 ] || fail "ok $ok + not done $not_done + failed $failed"
check_outputs "$work/out2" "$work/int.json"
before=$(($(rpcs_started a) + $(rpcs_started b)))
"$client_bin" batch skeletal "$work/clips" -o "$work/out2" --server "$target_a,$target_b" \
  --jobs 4 --timing --summary "$work/rerun.json" 2>"$work/rerun.err" && code=0 || code=$?
[ "$code" = 1 ] || fail "rerun exited $code: $(tail -3 "$work/rerun.err")"
after=$(($(rpcs_started a) + $(rpcs_started b)))
# The clips not done and the 2 bad ones (failed before any call) are done now; the rest skipped.
bad_not_done=$((2 - failed))
[ $((after - before)) = $((not_done - bad_not_done)) ] \
  || fail "the rerun sent $((after - before)) calls for $not_done clips not done"
[ "$(summary_field "$work/rerun.json" up_to_date)" = "$ok" ] || fail "rerun: up to date != $ok"
check_outputs "$work/out2" "$work/rerun.json"
echo "interrupt: $ok written, $not_done not done; the rerun sent $((after - before)) calls"
stop_server_as a
stop_server_as b
echo "PASS: batch fault e2e"

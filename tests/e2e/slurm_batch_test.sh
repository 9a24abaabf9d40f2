#!/usr/bin/env bash
# A real scheduler: Slurm (Debian's slurm-wlm, with munge), a controller and a node daemon on
# localhost started here (a slurm.conf in the scratch folder, loopback ports, nothing outside
# it), runs deploy/farm/koma-batch.sbatch as a job array of 4 tasks against two koma_servers on
# loopback. Checks:
#  1. the 4 tasks' outputs equal one unsharded `koma batch` run's, byte for byte, each clip in
#     the task koma's rule names, each task its own manifest and summary;
#  2. a second array: task 2 is stopped after its first outputs and cancelled (scancel: SIGTERM,
#     as a preempted or timed-out task gets), the other tasks finish; requeued
#     (scontrol requeue, same array index), task 2 sends exactly its unfinished clips, leaves the
#     other tasks' files alone, and the outputs again equal the single run's.
# Needs root (slurmd starts the tasks as their user). Usage:
#   slurm_batch_test.sh KOMA_SERVER KOMA PYTHON3 SBATCH_SCRIPT SAMPLES_DIR
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_named
set -euo pipefail
server_bin=$1 client_bin=$(realpath "$2") python=$3 sbatch_script=$4 samples=$5
here=$(cd "$(dirname "$0")" && pwd)

# shellcheck source=batch_lib.sh
source "$here/batch_lib.sh"  # and lib.sh

for tool in munged slurmctld slurmd sbatch squeue scontrol scancel; do
  command -v "$tool" >/dev/null || fail "no $tool: install slurm-wlm and munge (scripts/install-deps.sh)"
done
[ "$(id -u)" = 0 ] || fail "needs root: slurmd runs each task as the user who submitted it"

# 120 clips of 1,300 frames (the pitch ten times over, each clip's root moved its own amount):
# some milliseconds each, so that a task can be caught half done.
"$python" - "$samples/pitch.bvh" "$work/clips" 120 <<'PY'
import os, sys
pitch, root, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
text = open(pitch).read()
head, motion = text.split("MOTION\n")
frames = [line for line in motion.splitlines()[2:] if line.strip()]
for i in range(count):
    rows = []
    for r in range(10):
        for line in frames:
            values = line.split()
            values[0] = "%.4f" % (float(values[0]) + 0.25 * i + 0.01 * r)
            rows.append(" ".join(values))
    folder = os.path.join(root, "shot%02d" % (i % 7))
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "clip_%03d.bvh" % i), "w") as f:
        f.write(head + "MOTION\nFrames: %d\nFrame Time: 0.0416667\n" % len(rows) + "\n".join(rows) + "\n")
PY
start_named a --worker_threads=1
start_named b --worker_threads=1
servers="$target_a,$target_b"
started() { echo $(($(rpcs_started a) + $(rpcs_started b))); }
options=(--timing --omit 3 --jobs 1)

# The reference: one unsharded run.
expect_exit 0 "$work/single.err" "$client_bin" batch skeletal "$work/clips" -o "$work/single" \
  --server "$servers" "${options[@]}" --summary "$work/single.json"

# munge and Slurm, on loopback, everything in $work/slurm.
slurm=$work/slurm
mkdir -p "$slurm/state" "$slurm/spool"
head -c 1024 /dev/urandom >"$slurm/munge.key"
chmod 400 "$slurm/munge.key"
munged -F --force --key-file="$slurm/munge.key" --socket="$slurm/munge.sock" \
  --pid-file="$slurm/munged.pid" --seed-file="$slurm/munged.seed" --log-file="$work/munged.log" \
  2>>"$work/munged.log" &
munged_pid=$!
pids_to_kill+=("$munged_pid")
wait_until 10 test -S "$slurm/munge.sock" || fail "munged did not start"
host=$(hostname -s)
cat >"$slurm/slurm.conf" <<CONF
ClusterName=komatest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$slurm/munge.sock
StateSaveLocation=$slurm/state
SlurmdSpoolDir=$slurm/spool
SlurmctldPidFile=$slurm/slurmctld.pid
SlurmdPidFile=$slurm/slurmd.pid
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
KillWait=10
MinJobAge=600
SlurmdParameters=config_overrides
NodeName=komanode NodeHostname=$host NodeAddr=127.0.0.1 CPUs=4 State=UNKNOWN
PartitionName=koma Nodes=komanode Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$slurm/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >>"$work/slurmctld.log" 2>&1 &
slurmctld_pid=$!
pids_to_kill+=("$slurmctld_pid")
slurmd -D -N komanode -f "$SLURM_CONF" >>"$work/slurmd.log" 2>&1 &
slurmd_pid=$!
pids_to_kill+=("$slurmd_pid")
node_idle() { [ "$(sinfo -h -N -o %T 2>/dev/null)" = idle ]; }
wait_until 30 node_idle || fail "the Slurm node is not idle within 30 s: $(sinfo 2>&1)"

# submit OUTDIR: the deploy script as a 4-task array; prints the array's job id.
submit() {
  sbatch --parsable --requeue --array=0-3 --chdir="$work" --output="$work/slurm-%A_%a.log" \
    --export="ALL,KOMA_IN=$work/clips,KOMA_OUT=$1,KOMA_SERVER=$servers,KOMA_BIN=$client_bin" \
    "$sbatch_script" "${options[@]}"
}
# state ARRAY K: the state of task K (COMPLETED, CANCELLED, RUNNING, ...).
state() { scontrol -o show job "$1_$2" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p'; }
task_job_id() { scontrol -o show job "$1_$2" | sed -n 's/^JobId=\([0-9]*\) .*/\1/p'; }
all_done() {  # all_done ARRAY K...: every task K has ended
  local k
  for k in "${@:2}"; do
    case "$(state "$1" "$k")" in COMPLETED | FAILED | CANCELLED | TIMEOUT | OUT_OF_MEMORY) ;; *) return 1 ;; esac
  done
}
expect_completed() {
  local k
  for k in "${@:2}"; do
    [ "$(state "$1" "$k")" = COMPLETED ] ||
      fail "task $k of array $1: $(state "$1" "$k"): $(cat "$work/slurm-$1_$k.log" 2>/dev/null)"
  done
}
check_against_single() {
  "$python" "$here/batch_shard_check.py" 4 "$work/single.json" "$work/single" \
    "$1/summary.{k}-of-4.json" "$1" || fail "$2"
}

# 1. The array: four tasks, one batch.
before=$(started)
array=$(submit "$work/farm")
wait_until 120 all_done "$array" 0 1 2 3 || fail "array $array not done in 120 s: $(squeue 2>&1)"
expect_completed "$array" 0 1 2 3
[ "$(started)" = $((before + 120)) ] || fail "the array sent $(($(started) - before)) calls, want 120"
check_against_single "$work/farm" "the Slurm array against the single run"

# 2. Task 2 of a second array caught half done: stopped after its first output, cancelled.
#    Which outputs are task 2's: koma's rule, computed independently (batch_shard_check.py).
"$python" - "$work/single.json" >"$work/task2.txt" <<PY
import json, sys
sys.path.insert(0, "$here")
from batch_shard_check import relative_outputs, shard_of
for name in relative_outputs(json.load(open(sys.argv[1]))):
    if shard_of(name, 4) == 2:
        print(name)
PY
task2_total=$(wc -l <"$work/task2.txt")
[ "$task2_total" -ge 10 ] || fail "task 2 has only $task2_total clips"
task2_written() {
  local n=0 name
  while read -r name; do [ -f "$work/farm2/$name" ] && n=$((n + 1)); done <"$work/task2.txt"
  echo "$n"
}
array=$(submit "$work/farm2")
running2() { [ "$(state "$array" 2)" = RUNNING ]; }
wait_until 60 running2 || fail "task 2 did not start: $(state "$array" 2)"
job2=$(task_job_id "$array" 2)
koma_pid=""
find_koma() {  # the task's process: the batch script exec's koma
  local pid
  for pid in $(scontrol listpids "$job2" 2>/dev/null | awk 'NR > 1 {print $1}'); do
    [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = koma ] && koma_pid=$pid && return 0
  done
  return 1
}
wait_until 30 find_koma || fail "no koma process in task 2 (job $job2)"
poll_interval=0.005
first_written() { [ "$(task2_written)" -ge 1 ]; }
wait_until 60 first_written || fail "task 2 wrote nothing"
kill -STOP "$koma_pid"
poll_interval=0.1
scancel "${array}_2"  # SIGCONT, SIGTERM: koma stops sending, finishes and records what it has
cancelled() { [ "$(state "$array" 2)" = CANCELLED ]; }
wait_until 30 cancelled || fail "task 2 is $(state "$array" 2) after scancel"
wait_until 120 all_done "$array" 0 1 3 || fail "the other tasks did not end"
expect_completed "$array" 0 1 3
done_before=$("$python" -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["outputs"]))' \
  "$work/farm2/.koma-batch.2-of-4.json") || fail "task 2 left no manifest"
if [ "$done_before" -lt 1 ] || [ "$done_before" -ge "$task2_total" ]; then
  fail "task 2 was not caught half done: $done_before of $task2_total clips recorded"
fi
# The files of tasks 0, 1 and 3 (outputs, sheets, manifests, summaries) with their mtimes.
others_files() {
  "$python" - "$work/farm2" <<PY
import os, sys
sys.path.insert(0, "$here")
from batch_shard_check import shard_of
root = sys.argv[1]
for folder, _, names in os.walk(root):
    for name in sorted(names):
        path = os.path.join(folder, name)
        relative = os.path.relpath(path, root)
        clip = relative.replace(".timing.csv", ".bvh")
        if "2-of-4" in name or (not name.startswith(("summary.", ".koma-batch.")) and shard_of(clip, 4) == 2):
            continue
        print(relative, os.stat(path).st_mtime_ns)
PY
}
others_before=$(others_files | sort)

# Requeued: the same array index, the same shard; only the unfinished clips are sent.
before=$(started)
scontrol requeue "${array}_2"
scontrol update jobid="${array}_2" StartTime=now  # no requeue back-off in a test
completed2() { [ "$(state "$array" 2)" = COMPLETED ]; }
wait_until 120 completed2 || fail "requeued task 2: $(state "$array" 2): $(cat "$work/slurm-${array}_2.log")"
calls=$(($(started) - before))
[ "$calls" = $((task2_total - done_before)) ] ||
  fail "requeued task 2 sent $calls calls; $done_before of its $task2_total were done"
[ "$(summary_field "$work/farm2/summary.2-of-4.json" up_to_date)" = "$done_before" ] ||
  fail "requeued task 2's summary: $(head -20 "$work/farm2/summary.2-of-4.json")"
[ "$(others_files | sort)" = "$others_before" ] || fail "requeued task 2 touched other tasks' files"
check_against_single "$work/farm2" "the array with task 2 cancelled and requeued"

kill -TERM "$slurmd_pid" "$slurmctld_pid"
reap "$slurmd_pid" || true
reap "$slurmctld_pid" || true
kill -TERM "$munged_pid"
reap "$munged_pid" || true
stop_server_as a
stop_server_as b
echo "PASS: Slurm array of 4 = 1 run over 120 clips; task 2 cancelled at $done_before/$task2_total" \
  "and requeued sent $calls calls"

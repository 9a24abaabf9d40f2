#!/usr/bin/env bash
# End to end: `koma batch --shard K/N` and `--shard-from-env` against two real koma_servers on
# loopback. Five tasks run at once over 120 generated clips; together they write exactly the
# files one unsharded run writes, byte for byte, each task its own manifest and summary, each
# clip in the task an independent implementation of the rule names. A rerun of one task sends
# no call; a touched input and a deleted output are redone by their own tasks only; the
# scheduler's variables (Kubernetes, Slurm, KOMA_SHARD_*), the Flamenco job type's tasks, and
# bad values.
# Usage: batch_shard_e2e_test.sh KOMA_SERVER KOMA PYTHON3 DEPLOY_DIR
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_named
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 deploy=$4
here=$(cd "$(dirname "$0")" && pwd)

# shellcheck source=batch_lib.sh
source "$here/batch_lib.sh"  # and lib.sh

"$python" "$here/batch_make_clips.py" "$work/clips" 120 0 0 34
rm -r "$work/clips/bvh/bad"
start_named a --worker_threads=1
start_named b --worker_threads=1
servers="$target_a,$target_b"
started() { echo $(($(rpcs_started a) + $(rpcs_started b))); }
batch=("$client_bin" batch skeletal "$work/clips/bvh" --server "$servers" --timing --omit 3)

# 1. One unsharded run, then five tasks at once: the same files, a partition of the clips.
expect_exit 0 "$work/single.err" "${batch[@]}" -o "$work/single" --summary "$work/single.json"
before=$(started)
task_pids=()
for k in 0 1 2 3 4; do
  "${batch[@]}" -o "$work/sharded" --shard "$k/5" --summary "$work/sum.json" 2>"$work/task$k.err" &
  task_pids+=("$!")
  pids_to_kill+=("$!")
done
for k in 0 1 2 3 4; do
  reap "${task_pids[$k]}" || fail "task $k/5 failed: $(cat "$work/task$k.err")"
done
[ "$(started)" = $((before + 120)) ] || fail "five tasks sent $(($(started) - before)) calls, want 120"
grep -q "^koma batch: task 3/5: [0-9]* of the batch's 120 clips" "$work/task3.err" ||
  fail "no task line: $(cat "$work/task3.err")"
[ ! -e "$work/sum.json" ] || fail "a task wrote the unsharded summary path"
"$python" "$here/batch_shard_check.py" 5 "$work/single.json" "$work/single" \
  "$work/sum.{k}-of-5.json" "$work/sharded" || fail "the five tasks against the single run"

# 2. A rerun of one task sends no call and finds its clips up to date.
before=$(started)
expect_exit 0 "$work/rerun.err" "${batch[@]}" -o "$work/sharded" --shard 2/5 --summary "$work/re.json"
[ "$(started)" = "$before" ] || fail "the rerun of task 2 sent $(($(started) - before)) calls"
want=$(summary_field "$work/sum.2-of-5.json" total)
[ "$(summary_field "$work/re.2-of-5.json" up_to_date)" = "$want" ] || fail "task 2 rerun: not all up to date"

# 3. A touched input and a deleted output: their own tasks redo them, the others send nothing.
#    Which task a clip is in comes from task 0's and task 1's summaries.
first_clip() {  # first_clip SUMMARY: the input and output of its first clip
  "$python" -c 'import json,sys; f=json.load(open(sys.argv[1]))["files"][0]; print(f["input"], f["output"])' "$1"
}
read -r touched_in _ < <(first_clip "$work/sum.0-of-5.json")
read -r _ deleted_out < <(first_clip "$work/sum.1-of-5.json")
sleep 0.05
touch "$touched_in"
rm "$deleted_out"
for k in 0 1 2 3 4; do
  before=$(started)
  expect_exit 0 "$work/redo$k.err" "${batch[@]}" -o "$work/sharded" --shard "$k/5" --quiet
  calls=$(($(started) - before))
  want=0
  if [ "$k" -le 1 ]; then want=1; fi
  [ "$calls" = "$want" ] || fail "task $k/5 after a touch and a delete: $calls calls, want $want"
done
[ -s "$deleted_out" ] || fail "task 1 did not write $deleted_out again"
"$python" "$here/batch_shard_check.py" 5 "$work/single.json" "$work/single" \
  "$work/sum.{k}-of-5.json" "$work/sharded" || fail "after the redo"

# 4. --shard-from-env: Slurm's variables (--array=1-3, so ID 3 is index 2 of 3), a Kubernetes
#    Indexed Job's, koma's own; each task's clips as --shard K/N would choose them.
SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=3 \
  expect_exit 0 "$work/env.err" "${batch[@]}" -o "$work/env" --shard-from-env --summary "$work/env.json"
JOB_COMPLETION_INDEX=0 KOMA_SHARD_COUNT=3 \
  expect_exit 0 "$work/env.err" "${batch[@]}" -o "$work/env" --shard-from-env --summary "$work/env.json"
KOMA_SHARD_INDEX=1 KOMA_SHARD_COUNT=3 JOB_COMPLETION_INDEX=2 \
  expect_exit 0 "$work/env.err" "${batch[@]}" -o "$work/env" --shard-from-env --summary "$work/env.json"
"$python" "$here/batch_shard_check.py" 3 "$work/single.json" "$work/single" \
  "$work/env.{k}-of-3.json" "$work/env" || fail "the tasks from the environment"

# 5. The Flamenco job type (deploy/farm/koma-batch.js), compiled as the manager would, for 4
#    tasks: its commands, run at once, do what the single run did.
node "$here/flamenco_compile.js" "$deploy/farm/koma-batch.js" "$(printf \
  '{"clips": "%s", "output": "%s", "server": "%s", "tasks": 4, "extra_args": "--timing --omit 3"}' \
  "$work/clips/bvh" "$work/flamenco" "$servers")" >"$work/flamenco.jsonl" ||
  fail "the Flamenco job type does not compile"
[ "$(wc -l <"$work/flamenco.jsonl")" = 4 ] || fail "Flamenco: $(cat "$work/flamenco.jsonl")"
task_pids=()
while read -r line; do
  mapfile -t args < <("$python" -c 'import json,sys; print("\n".join(json.loads(sys.argv[1])["args"]))' "$line")
  "$client_bin" "${args[@]}" 2>>"$work/flamenco.err" &
  task_pids+=("$!")
  pids_to_kill+=("$!")
done <"$work/flamenco.jsonl"
for pid in "${task_pids[@]}"; do reap "$pid" || fail "a Flamenco task failed: $(cat "$work/flamenco.err")"; done
"$python" "$here/batch_shard_check.py" 4 "$work/single.json" "$work/single" \
  "$work/flamenco/summary.{k}-of-4.json" "$work/flamenco" || fail "the Flamenco tasks"

# 6. More tasks than clips: the empty tasks succeed with nothing to do.
"$python" "$here/batch_make_clips.py" "$work/few" 2 0 0 5
rm -r "$work/few/bvh/bad"
for k in $(seq 0 9); do
  expect_exit 0 "$work/few.err" "$client_bin" batch skeletal "$work/few/bvh" -o "$work/few_out" \
    --server "$target_a" --shard "$k/10" --json >"$work/few.json"
done
[ "$(find "$work/few_out" -name '*.bvh' | wc -l)" = 2 ] || fail "10 tasks over 2 clips"

# 7. Usage errors, exit 2, naming the value.
expect_error 2 "--shard 5/5: task index 5 is outside 0..4 (the index counts from 0)" \
  "${batch[@]}" -o "$work/bad" --shard 5/5
expect_error 2 "--shard 1of4: want K/N" "${batch[@]}" -o "$work/bad" --shard 1of4
expect_error 2 "excludes --shard-from-env\|--shard-from-env excludes" \
  "${batch[@]}" -o "$work/bad" --shard 1/4 --shard-from-env
env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX -u KOMA_SHARD_INDEX \
  "$client_bin" batch skeletal "$work/clips/bvh" -o "$work/bad" --shard-from-env \
  2>"$work/err.txt" && fail "--shard-from-env without variables succeeded"
grep -q "none of KOMA_SHARD_INDEX, JOB_COMPLETION_INDEX" "$work/err.txt" || fail "$(cat "$work/err.txt")"
JOB_COMPLETION_INDEX=1 expect_error 2 "JOB_COMPLETION_INDEX is set but KOMA_SHARD_COUNT is not" \
  "${batch[@]}" -o "$work/bad" --shard-from-env
[ ! -e "$work/bad" ] || fail "a refused task created its output folder"

stop_server_as a
stop_server_as b
echo "PASS: 5 tasks = 1 run over 120 clips; reruns, env, empty tasks, usage errors"

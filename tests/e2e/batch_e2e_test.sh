#!/usr/bin/env bash
# End to end: `koma batch` over 1,055 generated clips (700 BVH, 200 motion3.json, 150 CSV,
# 5 bad) against two real koma_servers on loopback. Every good clip's outputs equal the
# single-file command's byte for byte, every bad one is listed with its error, exit code 1;
# a rerun sends no call (the servers' Prometheus counters), a touched input or new options
# redo exactly what they should; @lists, LipBlink and usage errors.
# Usage: batch_e2e_test.sh KOMA_SERVER KOMA PYTHON3
# shellcheck disable=SC2154  # pid_NAME, port_NAME and target_NAME are set by start_named
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3
here=$(cd "$(dirname "$0")" && pwd)

# shellcheck source=batch_lib.sh
source "$here/batch_lib.sh"  # and lib.sh

"$python" "$here/batch_make_clips.py" "$work/clips" 700 200 150 7
start_named a --worker_threads=1
start_named b --worker_threads=1
servers="$target_a,$target_b"

started() { echo $(($(rpcs_started a) + $(rpcs_started b))); }

# 1. The skeletal batch (703 BVH, 3 bad: two the client cannot parse, one the server refuses)
#    and the curves batch (350 motion3.json and CSV, 2 bad), both spread over two servers.
expect_exit 1 "$work/sk.err" "$client_bin" batch skeletal "$work/clips/bvh" -o "$work/out/bvh" \
  --server "$servers" --timing --summary "$work/sk.json" --progress-every 0.2
expect_exit 1 "$work/cu.err" "$client_bin" batch curves "$work/clips/curves" \
  -o "$work/out/curves" --server "$servers" --jobs 3 --timing --on 2 --summary "$work/cu.json"
grep -q "^koma batch: 703 clips: 700 done, 0 up to date, 3 failed, 0 not done" "$work/sk.err" \
  || fail "skeletal summary line: $(tail -3 "$work/sk.err")"
grep -q "^koma batch: 352 clips: 350 done, 0 up to date, 2 failed, 0 not done" "$work/cu.err" \
  || fail "curves summary line: $(tail -3 "$work/cu.err")"
grep -q "^koma batch: .*/703 (.*%), .* clips/s" "$work/sk.err" \
  || fail "no plain progress line on a non-terminal stderr"
grep -q "one_frame.bvh: INVALID_ARGUMENT: motion.frame_count: 1 frames" "$work/sk.err" \
  || fail "the server's refusal is not reported with its code"
[ -z "$(find "$work/out" -name '*.tmp')" ] || fail "temporary files left: $(find "$work/out" -name '*.tmp')"
calls_a=$(rpcs_started a) calls_b=$(rpcs_started b)
[ "$((calls_a + calls_b))" = 1051 ] || fail "servers saw $calls_a + $calls_b calls, want 701 + 350"
[ "$calls_a" -gt 100 ] && [ "$calls_b" -gt 100 ] || fail "calls not spread: $calls_a / $calls_b"

# 2. Every output and timing sheet equals the single command's; every bad clip is listed.
"$python" "$here/batch_check.py" "$client_bin" "$target_a" skeletal "$work/sk.json" \
  "$work/sk.err" "$work/clips/bad.txt" "$work/clips" -- || fail "skeletal outputs"
"$python" "$here/batch_check.py" "$client_bin" "$target_b" curves "$work/cu.json" \
  "$work/cu.err" "$work/clips/bad.txt" "$work/clips" -- --on 2 || fail "curves outputs"

# 3. A rerun sends no call, except for the clip the server refused (a failed clip is retried).
before=$(started)
expect_exit 1 "$work/sk2.err" "$client_bin" batch skeletal "$work/clips/bvh" -o "$work/out/bvh" \
  --server "$servers" --timing --summary "$work/sk2.json"
expect_exit 1 "$work/cu2.err" "$client_bin" batch curves "$work/clips/curves" \
  -o "$work/out/curves" --server "$servers" --timing --on 2 --summary "$work/cu2.json"
after=$(started)
[ "$after" = $((before + 1)) ] || fail "the rerun sent $((after - before)) calls, want 1"
[ "$(summary_field "$work/sk2.json" up_to_date)" = 700 ] || fail "skeletal rerun: not 700 up to date"
[ "$(summary_field "$work/cu2.json" up_to_date)" = 350 ] || fail "curves rerun: not 350 up to date"

# 4. A touched input is redone alone; other options (or --force) redo every clip.
sleep 0.05
touch "$work/clips/curves/g03/clip_0013.motion3.json"
before=$(started)
expect_exit 1 "$work/cu3.err" "$client_bin" batch curves "$work/clips/curves" \
  -o "$work/out/curves" --server "$servers" --timing --on 2 --quiet
[ "$(started)" = $((before + 1)) ] || fail "a touched input: $(($(started) - before)) calls, want 1"
[ "$(grep -c . "$work/cu3.err")" = 2 ] || fail "--quiet printed more than the 2 failures"
before=$(started)
expect_exit 1 "$work/cu4.err" "$client_bin" batch curves "$work/clips/curves" \
  -o "$work/out/curves" --server "$servers" --timing --on 3 --summary "$work/cu4.json"
[ "$(started)" = $((before + 350)) ] || fail "--on 3 after --on 2: $(($(started) - before)) calls"
"$python" "$here/batch_check.py" "$client_bin" "$target_a" curves "$work/cu4.json" \
  "$work/cu4.err" "$work/clips/bad.txt" "$work/clips" -- --on 3 || fail "curves --on 3 outputs"
before=$(started)
expect_exit 1 "$work/cu5.err" "$client_bin" batch curves "$work/clips/curves" \
  -o "$work/out/curves" --server "$servers" --timing --on 3 --force --quiet
[ "$(started)" = $((before + 350)) ] || fail "--force: $(($(started) - before)) calls, want 350"

# 5. An @list of files and a folder (outputs: files by name, the folder's by their path in
#    it), all good: exit 0. LipBlink on the motion3 clips with reports, against one server.
{
  echo "# clips picked by hand"
  echo "$work/clips/bvh/g01/clip_0001.bvh"
  echo ""
  echo "$work/clips/bvh/g02/clip_0002.bvh"
  echo "$work/clips/bvh/g05"
} >"$work/list.txt"
expect_exit 0 "$work/list.err" "$client_bin" batch skeletal "@$work/list.txt" -o "$work/listed" \
  --server "$target_b" --summary "$work/list.json"
[ "$(summary_field "$work/list.json" ok)" = 72 ] || fail "@list: $(cat "$work/list.err")"
cmp -s "$work/listed/clip_0001.bvh" "$work/out/bvh/g01/clip_0001.bvh" || fail "@list output"
cmp -s "$work/listed/clip_0005.bvh" "$work/out/bvh/g05/clip_0005.bvh" || fail "@list folder output"
# Another (older) input of the same name into the same folder is not "up to date".
mkdir "$work/other"
cp "$work/clips/bvh/g02/clip_0002.bvh" "$work/other/clip_0001.bvh"
touch -d 2020-01-01 "$work/other/clip_0001.bvh"
before=$(started)
expect_exit 0 "$work/other.err" "$client_bin" batch skeletal "$work/other/clip_0001.bvh" \
  -o "$work/listed" --server "$target_b"
[ "$(started)" = $((before + 1)) ] || fail "an older input of the same name was skipped"
cmp -s "$work/listed/clip_0001.bvh" "$work/out/bvh/g02/clip_0002.bvh" || fail "same-name output"
mkdir "$work/lip_in"
cp "$work"/clips/curves/g0[0-2]/*.motion3.json "$work/lip_in/"
expect_exit 0 "$work/lip.err" "$client_bin" batch lipblink "$work/lip_in" -o "$work/lip_out" \
  --server "$target_a" --mouth Param0 --eyes Param1 --seed 7 --report --summary "$work/lip.json"
: >"$work/no_bad.txt"
"$python" "$here/batch_check.py" "$client_bin" "$target_a" lipblink "$work/lip.json" \
  "$work/lip.err" "$work/no_bad.txt" "$work/lip_in" -- --mouth Param0 --eyes Param1 --seed 7 \
  || fail "lipblink outputs"

# 6. Usage errors: exit 2 with the problem named, before any call.
before=$(started)
expect_exit 2 "$work/u1.err" "$client_bin" batch skeletal "$work/nowhere" -o "$work/u" \
  --server "$servers"
grep -q "nowhere: no such file or folder" "$work/u1.err" || fail "missing input: $(cat "$work/u1.err")"
echo "$work/clips/bvh/missing.bvh" >"$work/bad_list.txt"
expect_exit 2 "$work/u2.err" "$client_bin" batch skeletal "@$work/bad_list.txt" -o "$work/u" \
  --server "$servers"
grep -q "bad_list.txt:1: .*missing.bvh: no such file or folder" "$work/u2.err" \
  || fail "missing list entry: $(cat "$work/u2.err")"
expect_exit 2 "$work/u3.err" "$client_bin" batch curves "$work/clips/curves" -o "$work/u" \
  --omit 3 --server "$servers"
grep -q -- "unknown option or extra argument --omit" "$work/u3.err" \
  || fail "an option of another RPC: $(cat "$work/u3.err")"
expect_exit 2 "$work/u4.err" "$client_bin" batch skeletal "$work/clips/bvh/g01/clip_0001.bvh" \
  "$work/listed/clip_0001.bvh" -o "$work/u" --server "$servers"
grep -q "would both write" "$work/u4.err" || fail "two inputs, one output: $(cat "$work/u4.err")"
expect_exit 2 "$work/u5.err" "$client_bin" batch morph "$work/clips" -o "$work/u"
grep -q 'unknown RPC "morph"' "$work/u5.err" || fail "an unknown RPC: $(cat "$work/u5.err")"
mkdir "$work/empty"
expect_exit 2 "$work/u6.err" "$client_bin" batch curves "$work/empty" -o "$work/u" --server "$servers"
grep -q "no input clips" "$work/u6.err" || fail "an empty folder: $(cat "$work/u6.err")"
[ "$(started)" = "$before" ] || fail "a usage error sent calls"

# 7. Faults and the rest, on a few clips: a dead server is retried a bounded number of times
#    and each clip reported; RESOURCE_EXHAUSTED (a server with no queue) is retried until done;
#    an output folder inside the input folder is never searched; a terminal gets a live bar.
mkdir -p "$work/few"
cp "$work"/clips/bvh/g04/clip_00[0-3]4.bvh "$work/few/"
dead=$("$python" -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
expect_exit 1 "$work/dead.err" "$client_bin" batch skeletal "$work/few" -o "$work/dead" \
  --server "127.0.0.1:$dead" --retries 2 --jobs 4 --summary "$work/dead.json"
[ "$(grep -c "UNAVAILABLE: .*(after 3 attempts)" "$work/dead.err")" = 4 ] \
  || fail "a dead server: $(cat "$work/dead.err")"
[ -z "$(find "$work/dead" -name '*.bvh*')" ] || fail "a dead server: files written"
start_named c --worker_threads=1 --max_queued=0 --inline_max_bytes=0
expect_exit 0 "$work/busy.err" "$client_bin" batch skeletal "$work/clips/bvh/g06" \
  -o "$work/busy" --server "$target_c" --jobs 8 --retries 60 --summary "$work/busy.json"
[ "$(summary_field "$work/busy.json" retried)" -gt 0 ] || fail "RESOURCE_EXHAUSTED never happened"
[ "$(summary_field "$work/busy.json" ok)" = 70 ] || fail "busy server: $(tail -2 "$work/busy.err")"
stop_server_as c
timeout 60 "$client_bin" batch skeletal "$work/few" -o "$work/few/out" --server "$servers" \
  --json >"$work/in1.json" 2>"$work/in1.err" || fail "--json: $(cat "$work/in1.err")"
[ "$(summary_field "$work/in1.json" ok)" = 4 ] || fail "--json on stdout: $(cat "$work/in1.json")"
expect_exit 0 "$work/in2.err" "$client_bin" batch skeletal "$work/few" -o "$work/few/out" \
  --server "$servers" --summary "$work/in2.json"
[ "$(summary_field "$work/in2.json" total)" = 4 ] && [ "$(summary_field "$work/in2.json" up_to_date)" = 4 ] \
  || fail "outputs inside the input folder became inputs: $(cat "$work/in2.err")"
rm -rf "$work/few/out"
timeout 60 script -qec "$client_bin batch skeletal $work/few -o $work/tty --server $servers" \
  /dev/null >"$work/tty.txt" </dev/null || fail "under a terminal: $(cat "$work/tty.txt")"
grep -q $'\r\033\[K\[=*' "$work/tty.txt" || fail "no live bar on a terminal: $(od -c "$work/tty.txt" | head)"
grep -q "4 clips: 4 done" "$work/tty.txt" || fail "no summary on a terminal"

stop_server_as a
stop_server_as b
echo "PASS: batch e2e"

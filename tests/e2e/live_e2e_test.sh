#!/usr/bin/env bash
# End to end: `koma live` against the real koma_server on a free loopback port (issue 44):
# the bundled voice at once (--speed 0) and at real time (--seconds 3, --record), ALSA's null
# device, Ctrl-C, the error cases, and the acceptance: streamed recordings (the sample, and
# espeak-ng + sox takes at 16, 48 and 44.1 kHz stereo float, and Ogg Vorbis) give after the
# first second the speech of `koma lipblink --audio` within one grid frame at lookahead 3, and
# at every lookahead exactly the core's live analysis of the file (tests/e2e/live_check.py).
# Usage: live_e2e_test.sh KOMA_SERVER KOMA PYTHON SAMPLES_DIR LIVE_VOICE_COMPARE
set -euo pipefail
server_bin=$1 koma=$2 python=$3 samples=$4 compare_bin=$5
check="$(dirname "$0")/live_check.py"

source "$(dirname "$0")/lib.sh"

start_server "$server_bin"
voice="$samples/voice.flac"  # 3.82 s: 92 grid frames at 24 fps

# 1. The whole file at once: one line per grid frame from 0, every field.
"$koma" live --input "$voice" --json --speed 0 --server "$target" >"$work/fast.jsonl" \
  2>"$work/fast.err" || fail "koma live --speed 0: $(cat "$work/fast.err")"
"$python" "$check" lines "$work/fast.jsonl" --frames 92 || fail "--speed 0: the JSON lines"
grep -q "koma live: 92 frames (3.83 s at 24 fps): speech in 53 frames (2 runs)" \
  "$work/fast.err" || fail "--json: the summary on stderr: $(cat "$work/fast.err")"

# 2. Real time for 3 s with --record: 72 frames, no sooner than the audio (a frame cannot come
# before the lookahead's audio is sent: 83 ms at lookahead 2, less a chunk of 10 ms each side).
start_ns=$(date +%s%N)
"$koma" live --input "$voice" --json --seconds 3 --record "$work/rec.motion3.json" -q \
  --server "$target" >"$work/rt.jsonl" || fail "koma live --seconds 3 --record failed"
elapsed_ms=$((($(date +%s%N) - start_ns) / 1000000))
[ "$elapsed_ms" -ge 2950 ] || fail "3 s of audio at real time took only $elapsed_ms ms"
"$python" "$check" lines "$work/rt.jsonl" --frames 72 || fail "real time: the JSON lines"
"$python" - "$work/rt.jsonl" <<'PY' || fail "real time: wall_late_ms"
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
steady = [l["wall_late_ms"] for l in lines if l["late_ms"] > 80]  # not the stream's last frames
assert len(steady) >= 60, len(steady)
steady.sort()
assert steady[len(steady) // 2] >= 60, steady  # the lookahead's audio was waited for
print("wall_late_ms: median %.1f, max %.1f" % (steady[len(steady) // 2], steady[-1]))
PY
# Real time decides what --speed 0 did: every frame but the last two (lookahead 2), which the
# cut at 3 s decides on less audio.
"$python" - "$work/rt.jsonl" "$work/fast.jsonl" <<'PY' || fail "real time against --speed 0"
import json, sys
def frames(path):
    return [{k: v for k, v in json.loads(l).items() if not k.startswith("wall_")}
            for l in open(path)]
rt, fast = frames(sys.argv[1]), frames(sys.argv[2])
assert rt[:70] == fast[:70], [(a, b) for a, b in zip(rt, fast) if a != b][:2]
PY
"$python" "$check" record "$work/rec.motion3.json" "$work/rt.jsonl" || fail "--record"
"$koma" curves "$work/rec.motion3.json" -o "$work/rec.curves.motion3.json" --server "$target" \
  >/dev/null || fail "koma curves cannot read the --record file"
"$koma" lipblink "$work/rec.motion3.json" -o "$work/rec.lipblink.motion3.json" \
  --server "$target" >"$work/rec.summary" || fail "koma lipblink cannot read the --record file"
grep -q "rec.motion3.json: 73 frames at 24 fps" "$work/rec.summary" ||
  fail "koma lipblink on the record: $(cat "$work/rec.summary")"

# --record - writes the motion3.json on stdout, the human lines then go to stderr.
"$koma" live --input "$voice" --speed 0 --record - --server "$target" >"$work/stdout.motion3.json" \
  2>"$work/stdout.err" || fail "koma live --record -: $(cat "$work/stdout.err")"
cmp "$work/stdout.motion3.json" <("$koma" live --input "$voice" --speed 0 -q --record - \
  --server "$target") || fail "--record -: not the motion3.json alone"
grep -q "koma live: 92 frames" "$work/stdout.err" || fail "--record -: the summary not on stderr"
"$python" -c 'import json, sys; assert json.load(open(sys.argv[1]))["Meta"]["Duration"] == 92 / 24' \
  "$work/stdout.motion3.json" || fail "--record -: the motion3.json"

# 3. The capture path on ALSA's null device (silence): 1 s, 24 frames, none speech.
"$koma" live --device null --seconds 1 --json -q --server "$target" >"$work/null.jsonl" \
  2>"$work/null.err" || fail "koma live --device null: $(cat "$work/null.err")"
"$python" "$check" lines "$work/null.jsonl" --frames 24 --silent || fail "--device null"

# 4. Ctrl-C: the audio ends, the last frames are read, the record written, exit 0.
"$koma" live --input "$voice" --json --record "$work/int.motion3.json" -q --server "$target" \
  >"$work/int.jsonl" 2>"$work/int.err" &
live_pid=$!
pids_to_kill+=("$live_pid")
lines_at_least() { [ "$(wc -l <"$work/int.jsonl")" -ge "$1" ]; }
wait_until 10 lines_at_least 12 || fail "koma live: no frames within 10 s"
kill -INT "$live_pid"
code=0
reap "$live_pid" || code=$?
[ "$code" = 0 ] || fail "koma live after Ctrl-C exited $code: $(cat "$work/int.err")"
"$python" "$check" lines "$work/int.jsonl" || fail "Ctrl-C: the JSON lines"
frames=$(wc -l <"$work/int.jsonl")
[ "$frames" -lt 92 ] || fail "Ctrl-C did not end the audio ($frames frames)"
"$python" "$check" record "$work/int.motion3.json" "$work/int.jsonl" || fail "Ctrl-C: --record"

# The reader of --json's pipe leaving ends the session as Ctrl-C does (exit 0, the record).
set +o pipefail
"$koma" live --input "$voice" --json -q --record "$work/pipe.motion3.json" --server "$target" |
  head -n 1 >"$work/pipe.jsonl"
code=${PIPESTATUS[0]}
set -o pipefail
[ "$code" = 0 ] || fail "koma live --json | head -n 1 exited $code"
"$python" "$check" lines "$work/pipe.jsonl" --frames 1 || fail "| head -n 1: the line"
grep -q '"ParamMouthOpenY"' "$work/pipe.motion3.json" || fail "| head: no --record written"

# A server shutting down mid-stream: its UNAVAILABLE message, exit 1, the record still written.
start_server_as doomed "$server_bin"
"$koma" live --input "$voice" --json -q --record "$work/doomed.motion3.json" \
  --server "$target_doomed" >"$work/doomed.jsonl" 2>"$work/doomed.err" &
live_pid=$!
pids_to_kill+=("$live_pid")
lines_of_doomed() { [ "$(wc -l <"$work/doomed.jsonl")" -ge "$1" ]; }
wait_until 10 lines_of_doomed 6 || fail "koma live on the doomed server: no frames"
stop_server_as doomed
code=0
reap "$live_pid" || code=$?
[ "$code" = 1 ] || fail "koma live after its server stopped exited $code"
grep -q "koma: UNAVAILABLE: the server is shutting down" "$work/doomed.err" ||
  fail "the server's shutdown message: $(cat "$work/doomed.err")"
"$python" "$check" record "$work/doomed.motion3.json" "$work/doomed.jsonl" ||
  fail "--record after the server stopped"

# 5. Errors: the file, the device, the server's message, usage.
expect_error 1 "koma: --input $work/missing.wav: cannot read" \
  "$koma" live --input "$work/missing.wav" --server "$target"
expect_error 1 "not a recording libsndfile can read" \
  "$koma" live --input "$work/rt.jsonl" --server "$target"
expect_error 1 "koma: --device no_such_device: cannot open it for capture" \
  "$koma" live --device no_such_device --seconds 1 --server "$target"
expect_error 1 "koma: INVALID_ARGUMENT: setup.lookahead_frames: 5 must be in \[0, 3\]" \
  "$koma" live --input "$voice" --lookahead 5 --server "$target"
expect_error 1 "koma: INVALID_ARGUMENT: setup.timing_fps" \
  "$koma" live --input "$voice" --timing-fps 2000 --server "$target"
expect_error 2 "koma live: --input .* and --device null: give one audio source" \
  "$koma" live --input "$voice" --device null --server "$target"
expect_error 1 "koma: --record: cannot write $work/no/x.motion3.json" \
  "$koma" live --input "$voice" --record "$work/no/x.motion3.json" --server "$target"
expect_error 2 "koma live: --speed: needs --input FILE" \
  "$koma" live --device null --speed 0 --server "$target"
expect_error 1 "koma: UNAVAILABLE: cannot reach koma_server at 127.0.0.1:" \
  "$koma" live --input "$voice" --speed 0 --server "127.0.0.1:$(free_port)"

# 6. The acceptance: live speech against offline speech, and the wire against the core.
mkdir -p "$work/voices"
"$python" "$check" recordings "$work/voices" >"$work/voices.txt" || fail "making the recordings"
mapfile -t recordings <"$work/voices.txt"
"$python" "$check" agree "$koma" "$target" "$work/voices" --core "$compare_bin" \
  "$voice" "${recordings[@]}" || fail "live speech against koma lipblink --audio"

stop_server
echo "PASS"

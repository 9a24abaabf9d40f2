#!/usr/bin/env bash
# End to end: `koma batch lipblink --audio-beside`, the real koma_server on a free loopback
# port. Spine skeletons and Live2D motions, each with its own recording beside it (made by
# tests/testing/voice_recordings.py, and samples/voice.flac): every output and report is byte
# for byte what the single-file `koma lipblink IN --audio REC` writes; a recording among the
# inputs goes with its skeleton and writes nothing of its own; an input with no recording or
# with two fails alone, naming itself and the candidates; a rerun skips what is done and
# redoes an item whose recording is newer.
# Usage: batch_audio_beside_e2e_test.sh KOMA_SERVER KOMA SAMPLES_DIR SPINE_TESTDATA_DIR
#        TESTING_DIR
set -euo pipefail
server_bin=$1 client_bin=$2 samples=$3 data=$4 testing=$5
here=$(dirname "$0")

source "$here/lib.sh"

# Recordings: the test voices (espeak-ng + sox, a few seconds), and the sample.
python3 - "$testing" "$work/voices" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import voice_recordings
folder = sys.argv[2]
clean, _, _ = voice_recordings.make_clean(folder)
voice_recordings.variant(folder, clean, "short16k.wav", rate=16000)
PY
mkdir -p "$work/skel" "$work/motions"
cp "$samples/hero.json" "$work/skel/hero.json"
cp "$samples/voice.flac" "$work/skel/hero.flac"
cp "$data/hero-4.2.json" "$work/skel/villain.json"
cp "$work/voices/clean.wav" "$work/skel/villain.wav"
cp "$data/matt-3.7.json" "$work/skel/matt.json"
cp "$work/voices/short16k.wav" "$work/skel/matt.WAV"  # any case of the extension
cp "$samples/arm_head.motion3.json" "$work/motions/arm.motion3.json"
cp "$work/voices/clean.wav" "$work/motions/arm.wav"
cp "$samples/talk_blink.motion3.json" "$work/motions/talk.motion3.json"
cp "$samples/voice.flac" "$work/motions/talk.flac"

start_server "$server_bin"

# --- Spine skeletons: two named, one from an @list, and a paired recording named too.
spine=(--animation talk --mouth-slot mouth --eye-slot eyes --auto-blink 1.5 --seed 4
       --server "$target")
matt=(--animation shake_head --mouth-slot mouth --mouth-attachments mouth_a,mouth_c,mouth_d
      --seed 4 --server "$target")
echo "$work/skel/matt.json" >"$work/list.txt"
cd "$work"
"$client_bin" batch lipblink skel/hero.json skel/villain.json skel/hero.flac "${spine[@]}" \
  --audio-beside -o out --report --summary summary.json >batch.txt 2>&1 ||
  fail "koma batch lipblink --audio-beside failed: $(cat batch.txt)"
python3 - summary.json <<'PY' || fail "summary: $(cat summary.json)"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["total"] == 2 and s["ok"] == 2 and s["failed"] == 0, s
assert [(f["input"], f["audio"]) for f in s["files"]] == [
    ("skel/hero.json", "skel/hero.flac"), ("skel/villain.json", "skel/villain.wav")], s["files"]
PY
[ ! -e out/hero.motion3.json ] || fail "the paired recording was also processed on its own"
mkdir -p single
for name in hero:flac villain:wav; do
  stem=${name%%:*} ext=${name##*:}
  "$client_bin" lipblink "skel/$stem.json" --audio "skel/$stem.$ext" "${spine[@]}" \
    -o "single/$stem.json" --report "single/$stem.report.html" >/dev/null ||
    fail "single $stem failed"
  cmp -s "out/$stem.json" "single/$stem.json" || fail "batch $stem.json differs from the single run"
  cmp -s "out/$stem.report.html" "single/$stem.report.html" ||
    fail "batch $stem.report.html differs from the single run"
  grep -q "mouth_open" "out/$stem.json" || fail "$stem.json has no open mouth key"
done
grep -q "skel/hero.flac" out/hero.report.html || fail "the report does not name the recording"

# A folder of skeletons (the Spine flags make folders collect *.json; the recordings beside
# are found, not collected): the same files.
mkdir -p folder/sub
cp skel/hero.json skel/hero.flac folder/
cp skel/villain.json skel/villain.wav folder/sub/
"$client_bin" batch lipblink folder "${spine[@]}" --audio-beside -o out_folder \
  --summary folder.json >batch_folder.txt 2>&1 ||
  fail "batch over a folder of skeletons failed: $(cat batch_folder.txt)"
cmp -s out_folder/hero.json single/hero.json || fail "folder hero.json differs"
cmp -s out_folder/sub/villain.json single/villain.json || fail "folder sub/villain.json differs"
grep -q '"total": 2' folder.json || fail "folder summary: $(cat folder.json)"

# The @list skeleton (3.7, its own attachment names, the extension in upper case).
"$client_bin" batch lipblink @list.txt "${matt[@]}" --audio-beside -o out_matt \
  >batch_matt.txt 2>&1 || fail "batch @list failed: $(cat batch_matt.txt)"
"$client_bin" lipblink skel/matt.json --audio skel/matt.WAV "${matt[@]}" \
  -o single/matt.json >/dev/null || fail "single matt failed"
cmp -s out_matt/matt.json single/matt.json || fail "batch matt.json differs from the single run"

# --- Live2D motions: a folder of motions with their voices (the recordings are found in the
# folder too, and go with their motions).
"$client_bin" batch lipblink motions --audio-beside --seed 4 --auto-blink 2 --server "$target" \
  -o out_motions --report --summary motions.json >batch_motions.txt 2>&1 ||
  fail "batch motions failed: $(cat batch_motions.txt)"
python3 -c "
import json, sys
s = json.load(open('motions.json'))
assert s['total'] == 2 and s['ok'] == 2, s
" || fail "motions summary: $(cat motions.json)"
for name in arm:wav talk:flac; do
  stem=${name%%:*} ext=${name##*:}
  "$client_bin" lipblink "motions/$stem.motion3.json" --audio "motions/$stem.$ext" --seed 4 \
    --auto-blink 2 --server "$target" -o "single/$stem.motion3.json" \
    --report "single/$stem.report.html" >/dev/null || fail "single $stem failed"
  cmp -s "out_motions/$stem.motion3.json" "single/$stem.motion3.json" ||
    fail "batch $stem.motion3.json differs from the single run"
  cmp -s "out_motions/$stem.report.html" "single/$stem.report.html" ||
    fail "batch $stem.report.html differs from the single run"
done
# Not what a run without the recording writes (the recording went over the wire).
"$client_bin" lipblink motions/arm.motion3.json --seed 4 --auto-blink 2 --server "$target" \
  -o single/arm_no_voice.motion3.json >/dev/null 2>&1 || true
! cmp -s out_motions/arm.motion3.json single/arm_no_voice.motion3.json ||
  fail "the batch output equals a run without the recording"

# --- Rerun: all up to date; a newer recording redoes its skeleton only.
"$client_bin" batch lipblink skel/hero.json skel/villain.json "${spine[@]}" --audio-beside \
  -o out --report >rerun.txt 2>&1 || fail "rerun failed: $(cat rerun.txt)"
grep -q "2 clips: 0 done, 2 up to date" rerun.txt || fail "rerun: $(cat rerun.txt)"
touch -d '+2 seconds' skel/villain.wav
"$client_bin" batch lipblink skel/hero.json skel/villain.json "${spine[@]}" --audio-beside \
  -o out --report >rerun2.txt 2>&1 || fail "rerun 2 failed: $(cat rerun2.txt)"
grep -q "2 clips: 1 done, 1 up to date" rerun2.txt || fail "newer recording: $(cat rerun2.txt)"

# --- Errors, each failing its own item while the others are done.
mkdir -p bad
cp "$samples/hero.json" bad/alone.json         # no recording
cp "$samples/hero.json" bad/twice.json         # two recordings
cp "$samples/voice.flac" bad/twice.flac
cp "$work/voices/short16k.wav" bad/twice.wav
cp "$samples/voice.flac" bad/stray.flac        # a recording with no skeleton
cp "$samples/hero.json" bad/fine.json
cp "$samples/voice.flac" bad/fine.flac
expect_exit 1 bad.err "$client_bin" batch lipblink bad/alone.json bad/twice.json bad/stray.flac \
  bad/fine.json "${spine[@]}" --audio-beside -o out_bad --summary bad.json
python3 - bad.json <<'PY' || fail "bad summary: $(cat bad.json)"
import json, sys
s = json.load(open(sys.argv[1]))
status = {f["input"]: (f["status"], f.get("error", "")) for f in s["files"]}
assert s["ok"] == 1 and s["failed"] == 3, s
assert status["bad/fine.json"][0] == "ok", status
assert status["bad/alone.json"] == ("failed", "--audio-beside: no recording beside bad/alone.json "
    "(looked for alone.wav, alone.flac, alone.ogg, alone.oga, alone.opus, alone.mp3)"), status
assert status["bad/twice.json"] == ("failed", "--audio-beside: 2 recordings beside "
    "bad/twice.json: bad/twice.flac, bad/twice.wav (keep one of them there)"), status
assert status["bad/stray.flac"][0] == "failed" and \
    "bad/stray.flac is a recording with no input of its name beside it" in status["bad/stray.flac"][1], status
PY
grep -q "koma: bad/alone.json: --audio-beside: no recording beside\|--audio-beside: no recording beside bad/alone.json" bad.err ||
  fail "stderr does not name the skeleton: $(cat bad.err)"
[ -s out_bad/fine.json ] || fail "the good skeleton was not written"
# The recording gives the speech: --speech with it is refused once, up front.
expect_error 2 "--audio-beside and --speech: each recording gives its clip's speech" \
  "$client_bin" batch lipblink skel/hero.json "${spine[@]}" --audio-beside --speech 3-9 -o out_s
[ ! -e out_s ] || fail "a refused batch wrote its output folder"
# Only for lipblink.
expect_error 2 "audio-beside" "$client_bin" batch curves skel/hero.json --audio-beside -o out_c \
  --server "$target"

stop_server
echo "batch --audio-beside e2e: ok"

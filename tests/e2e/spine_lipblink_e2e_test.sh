#!/usr/bin/env bash
# End to end: the real koma_server on a free loopback port, `koma lipblink` on Spine skeletons
# (samples/hero.json 4.1 with samples/voice.flac; the real 3.7 export and the hand-written 3.8
# and 4.1 files), the written slot attachment timelines read by the independent evaluator
# (spine_eval.py): the mouth drawing at every 24 fps grid time equals the drawing of the
# Rhubarb cue the ordinary motion3 path writes for the same recording; blinks are closed, then
# half, then open; everything else in the file is unchanged.
# Usage: spine_lipblink_e2e_test.sh KOMA_SERVER KOMA PYTHON SAMPLES_DIR SPINE_TESTDATA_DIR
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 samples=$4 data=$5
here=$(dirname "$0")

source "$here/lib.sh"

start_server "$server_bin"

# A new animation "talk" from the recording, with auto-blinks.
"$client_bin" lipblink "$samples/hero.json" --animation talk --audio "$samples/voice.flac" \
  --mouth-slot mouth --mouth-attachments mouth_closed,mouth_mid,mouth_open \
  --eye-slot eyes --eye-attachments eyes_open,eyes_half,eyes_closed --auto-blink 1.5 \
  -o "$work/talk.json" --xdts "$work/talk.xdts" --server "$target" >"$work/talk.txt" ||
  fail "koma lipblink hero.json failed"
# The exposure sheet of the same answer: the slots as cell tracks.
grep -qF 'mouth (1 closed, 2 mid, 3 open)' "$work/talk.xdts" || fail "talk.xdts lacks the mouth track"
grep -qF 'eyes (1 open, 2 half, 3 closed)' "$work/talk.xdts" || fail "talk.xdts lacks the eye track"
grep -q 'animation "talk" (new), slot mouth' "$work/talk.txt" || fail "summary: $(cat "$work/talk.txt")"
# The same recording the ordinary way (a new motion3 at the skeleton's 30 fps), as cues.
"$client_bin" lipblink --audio "$samples/voice.flac" --fps 30 -o "$work/ref.motion3.json" \
  --cues "$work/ref.cues.json" --server "$target" >/dev/null || fail "koma lipblink --audio failed"
"$python" - "$here" "$samples/hero.json" "$work/talk.json" "$work/ref.cues.json" <<'PY' || fail "hero.json talk"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval as ev
before, after, cues = (json.load(open(p)) for p in sys.argv[2:5])
mouth = ev.check_attachment_keys(after, "talk", "mouth", ["mouth_closed", "mouth_mid", "mouth_open"])
eyes = ev.check_attachment_keys(after, "talk", "eyes", ["eyes_open", "eyes_half", "eyes_closed"])
assert after["skeleton"]["spine"] == before["skeleton"]["spine"]
assert all("time" not in k for k in after["animations"]["talk"]["slots"]["mouth"]["attachment"][:1]), "4.x omits time 0"
letter = {"A": "mouth_closed", "B": "mouth_closed", "G": "mouth_closed", "X": "mouth_closed",
          "C": "mouth_mid", "E": "mouth_mid", "F": "mouth_mid", "H": "mouth_mid", "D": "mouth_open"}
end = cues["metadata"]["duration"]
grid = int(end * 24)
checked = opened = 0
for g in range(grid):
    t = g / 24
    cue = next(c for c in cues["mouthCues"] if c["start"] <= t + 1e-9 < c["end"])
    want = letter[cue["value"]]
    got = ev.attachment_at(after, "talk", "mouth", t)
    assert got == want, f"{t:.4f} s (grid frame {g}): {got}, the motion3 path's cue {cue} is {want}"
    checked += 1
    opened += got != "mouth_closed"
assert opened > 10, f"only {opened} grid frames not closed"
# Blinks: closed, then half, then open (the anime blink), a few in the recording's length.
names = [n for _, n in eyes]
blinks = 0
for i, n in enumerate(names):
    if n == "eyes_closed":
        blinks += 1
        assert names[i - 1] == "eyes_open", names
        assert i + 1 == len(names) or names[i + 1] == "eyes_half", names
assert blinks >= 2, f"{blinks} blinks in {end} s at a 1.5 s mean"
# Nothing else changed.
del after["animations"]["talk"]
assert after == before, "the rest of the skeleton changed"
print(f"talk: {checked} grid frames checked, {len(mouth)} mouth keys, {blinks} blinks")
PY

# An existing animation: hero-4.1's walk closes the eyes 0.8 .. 0.9 s, a blink kept; --speech.
"$client_bin" lipblink "$data/hero-4.1.json" --animation walk --mouth-slot mouth --speech 3-20 \
  --eye-slot eyes -o "$work/walk.json" --server "$target" >/dev/null || fail "hero-4.1 walk failed"
"$python" - "$here" "$data/hero-4.1.json" "$work/walk.json" <<'PY' || fail "hero-4.1 walk"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval as ev
before, after = (json.load(open(p)) for p in sys.argv[2:4])
mouth = ev.check_attachment_keys(after, "walk", "mouth", ["mouth_closed", "mouth_mid", "mouth_open"])
eyes = ev.check_attachment_keys(after, "walk", "eyes", ["eyes_open", "eyes_half", "eyes_closed"])
# Speech 3-20 (frames at 30 fps): drawings only from 0.1 s, closed again from 20 / 30 s.
assert mouth[0][1] == "mouth_closed" and mouth[1][0] >= 0.1 - 1 / 24 and mouth[-1][1] == "mouth_closed"
assert mouth[-1][0] <= 20 / 30 + 1 / 24, mouth
closed = [t for t, n in eyes if n == "eyes_closed"]
assert len(closed) == 1 and abs(closed[0] - 0.8) <= 1 / 24, eyes
# The walk's bones, the head slot's colour timeline and the other animations are untouched.
for key in ("bones", "events", "drawOrder"):
    if key in before["animations"]["walk"]:
        assert after["animations"]["walk"][key] == before["animations"]["walk"][key], key
assert after["animations"]["walk"]["slots"]["head"] == before["animations"]["walk"]["slots"]["head"]
for key in after:
    if key != "animations":
        assert after[key] == before[key], key
assert {k: v for k, v in after["animations"].items() if k != "walk"} == \
    {k: v for k, v in before["animations"].items() if k != "walk"}
print("walk: mouth", len(mouth), "keys, eyes", eyes)
PY

# The 3.7 export: its eight mouths, three of them named; 3.x writes time 0.
"$client_bin" lipblink "$data/matt-3.7.json" --animation shake_head --mouth-slot mouth \
  --mouth-attachments mouth_a,mouth_c,mouth_d --speech 0-25 --timing-fps 0 \
  -o "$work/matt.json" --server "$target" >/dev/null || fail "matt-3.7 failed"
"$python" - "$here" "$work/matt.json" <<'PY' || fail "matt-3.7"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval as ev
after = json.load(open(sys.argv[2]))
keys = ev.check_attachment_keys(after, "shake_head", "mouth", ["mouth_a", "mouth_c", "mouth_d"], grid_fps=30)
assert after["animations"]["shake_head"]["slots"]["mouth"]["attachment"][0]["time"] == 0
assert len(keys) >= 5, keys
PY

# Bad names: the flag and the value in the message, exit 2; nothing written.
expect_error 2 '--mouth-slot no slot named "nose" (the skeleton has torso, head, mouth, eyes)' \
  "$client_bin" lipblink "$samples/hero.json" --animation talk --speech 0-9 --mouth-slot nose \
  -o "$work/never.json" --server "$target"
expect_error 2 '--mouth-attachments: "mouth_wide" is not an attachment of slot "mouth" in any skin (it has mouth_closed, mouth_mid, mouth_open)' \
  "$client_bin" lipblink "$samples/hero.json" --animation talk --speech 0-9 --mouth-slot mouth \
  --mouth-attachments mouth_closed,mouth_wide,mouth_open -o "$work/never.json" --server "$target"
expect_error 2 '--eye-attachments: expected three attachment names (open,half,closed), got 2' \
  "$client_bin" lipblink "$samples/hero.json" --animation walk --eye-slot eyes \
  --eye-attachments eyes_open,eyes_closed -o "$work/never.json" --server "$target"
expect_error 2 '--mouth-slot mouth: the mouth needs a voice' \
  "$client_bin" lipblink "$samples/hero.json" --animation walk --mouth-slot mouth \
  -o "$work/never.json" --server "$target"
expect_error 2 'is not a Spine skeleton' \
  "$client_bin" lipblink "$samples/talk_blink.motion3.json" --animation walk --mouth-slot mouth \
  -o "$work/never.json" --server "$target"
# Without the Spine flags a skeleton is refused, pointing at them (as before, for motion3 paths).
expect_error 1 "hero.json is a Spine skeleton: .koma lipblink. reads Live2D motion3.json or per-frame CSV; key a skeleton's mouth and eyes with --animation NAME" \
  "$client_bin" lipblink "$samples/hero.json" -o "$work/never.json" --server "$target"
expect_error 1 'is a Spine skeleton' \
  "$client_bin" lipblink --audio "$samples/voice.flac" --motion "$samples/hero.json" \
  -o "$work/never.json" --server "$target"
[ ! -e "$work/never.json" ] || fail "a refused run wrote its output"

stop_server
echo "spine lipblink e2e: ok"

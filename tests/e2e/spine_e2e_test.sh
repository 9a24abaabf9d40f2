#!/usr/bin/env bash
# End to end: the real koma_server on a free loopback port, the real `koma curves` on Spine
# skeletons (the real 3.7 export and the hand-written 3.8, 4.1 and 4.2 files), every written
# bone value checked on the 24 fps grid by an independent evaluator (spine_eval.py).
# Usage: spine_e2e_test.sh KOMA_SERVER KOMA PYTHON SPINE_TESTDATA_DIR
set -euo pipefail
server_bin=$1 client_bin=$2 python=$3 data=$4
here=$(dirname "$0")

source "$here/lib.sh"

start_server "$server_bin"

for name in matt-3.7 hero-3.8 hero-4.1 hero-4.2; do
  in="$data/$name.json"
  # Every animation with bone keys, on threes (the default) on the 24 fps grid.
  "$client_bin" curves "$in" -o "$work/$name.anime.json" --server "$target" \
    >"$work/$name.summary.txt" || fail "koma curves $name failed"
  grep -q '^animation "' "$work/$name.summary.txt" || fail "$name: summary names no animation"
  "$python" "$here/spine_eval.py" "$in" "$work/$name.anime.json" ||
    fail "$name: written values differ from the input's at the drawings' times"
  # The same bytes when the server parses and writes the file (--send-file).
  "$client_bin" curves "$in" -o "$work/$name.sent.json" --send-file --server "$target" \
    >/dev/null || fail "koma curves --send-file $name failed"
  cmp "$work/$name.anime.json" "$work/$name.sent.json" || fail "$name: --send-file wrote other bytes"
  # Nothing left to change: retiming the retimed skeleton writes back the same JSON.
  "$client_bin" curves "$work/$name.anime.json" -o "$work/$name.again.json" --server "$target" \
    >/dev/null || fail "the written $name does not read back"
  "$python" - "$work/$name.anime.json" "$work/$name.again.json" <<'PY' || fail "$name: a second retime changed it"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a == b
PY
done

# Keys are sacred (issue 40): the real 3.7 walk is a cycle, every bone value whose input ends
# where it starts ends there written (the torso's last key 0 was written as 11.3), and the
# torso's bounce keyed at 30 is drawn at 30 (it was 29.8).
"$python" - "$here" "$data/matt-3.7.json" "$work/matt-3.7.anime.json" <<'PY' || fail "matt walk: the loop does not close or a key is not drawn"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval
before, after = (json.load(open(p, encoding="utf-8")) for p in sys.argv[2:4])
closed = spine_eval.loop_closes(before, after, "walk")
assert closed == 2, closed  # torso/translate.x (flat) and .y (0, 30, 0)
torso = spine_eval.bone_values(after)["walk"]["torso/translate.y"]
keyed = spine_eval.bone_values(before)["walk"]["torso/translate.y"]
assert max(keyed.values) in torso.values, (max(keyed.values), torso.values)
print("matt walk:", closed, "bone values close their loop; the bounce", max(keyed.values), "is drawn")
PY
# --check-keys measures it: no keyed extreme or end missed on the walk.
"$client_bin" curves "$data/matt-3.7.json" -o "$work/matt-check.json" --animation walk --check-keys \
  --json --server "$target" >"$work/matt-check.summary.json" || fail "--check-keys failed"
"$python" - "$work/matt-check.summary.json" <<'PY' || fail "matt walk: --check-keys finds missed keys"
import json, sys
check = json.load(open(sys.argv[1]))["key_check"]
assert check["ends_missed"] == 0 and check["extremes_missed"] == 0, check
assert check["extremes"] > 0, check  # a 0.27 s cycle: 3 drawings, no rate to judge
PY

# A Bezier whose handle leaves its segment's time span, as the Spine editor writes it (its
# first handle dragged before the key: cx1 < the key's time), is read and retimed (it was
# refused), and the report marks its peak drawn. The root's key at 0.1667 s (frame 5, as Spine
# writes 1/6 s) makes the key pose; the head's peak keyed a frame later (0.2 s) joins it, so the
# drawing that holds the peak has its tau at frame 5, where the head is still rising: before
# keys were drawn koma showed that, short of the peak.
"$python" - "$work/handles.json" <<'PY'
import json, sys
skeleton = {
    "skeleton": {"spine": "4.1.24", "fps": 30},
    "bones": [{"name": "root"}, {"name": "head", "parent": "root"}],
    "animations": {"nod": {"bones": {
        "head": {"rotate": [
            {"curve": [-0.05, 5, 0.15, 20]},
            {"time": 0.2, "value": 20, "curve": [0.25, 20, 0.3, 0]},
            {"time": 0.4, "value": 0}]},
        "root": {"translate": [{"x": 0}, {"time": 0.1667, "x": 5}, {"time": 0.4, "x": 10}]}}}},
}
json.dump(skeleton, open(sys.argv[1], "w"), indent=1)
PY
"$client_bin" curves "$work/handles.json" -o "$work/handles.anime.json" --report "$work/handles.html" \
  --json --server "$target" >"$work/handles.summary.json" ||
  fail "a skeleton with a handle outside its segment was not retimed"
"$python" - "$here" "$work/handles.json" "$work/handles.html" <<'PY' || fail "the report does not show the handle skeleton's peak drawn"
import html, json, re, sys
sys.path.insert(0, sys.argv[1])
import spine_eval
before = json.load(open(sys.argv[2]))
page = open(sys.argv[3], encoding="utf-8").read()
data = json.loads(html.unescape(re.search(r'<script type="application/json" id="koma-data">(.*?)</script>', page, re.S).group(1)))
curve = [c for c in data["curves"] if c["id"] == "head/rotate"][0]
peak = [k for k in curve["keys"] if abs(k[0] - 0.2) < 1e-6]
assert peak and peak[0][1] == 20 and peak[0][2], curve["keys"]
# The drawing that shows it: its tau alone shows far less than the peak.
timeline = spine_eval.bone_values(before)["nod"]["head/rotate"]
at_tau = timeline.at(5 / 30)
assert abs(at_tau - 20) > 0.1, at_tau
print("handle outside its segment: peak 20 drawn; the drawing's tau alone shows", round(at_tau, 2))
PY
"$python" "$here/spine_eval.py" "$work/handles.json" "$work/handles.anime.json" ||
  fail "the handle skeleton's written values differ from the rule's"

# 30 fps on threes: 8 drawings a second (idle's keys are 1 s apart); only the named animation
# changes; everything koma does not retime is unchanged.
"$client_bin" curves "$data/hero-3.8.json" -o "$work/walk.json" --animation walk --server "$target" \
  --report "$work/walk.html" --timing "$work/walk.csv" --xdts "$work/walk.xdts" >/dev/null ||
  fail "--animation walk failed"
# The exposure sheet: one row per 24 fps grid frame (37 for the 1.5 s walk), the drawings
# numbered 1..N in order, N the drawing sheet's drawings, then the end mark.
"$python" - "$work/walk.xdts" "$work/walk.csv" <<'PY' || fail "walk: the XDTS sheet does not match the drawing sheet"
import csv, json, sys
text = open(sys.argv[1], encoding="utf-8").read()
first, _, rest = text.partition("\n")
assert first == "exchangeDigitalTimeSheet Save Data", first
table = json.loads(rest)["timeTables"][0]
assert table["duration"] == 37, table["duration"]
cells = [(e["frame"], e["data"][0]["values"][0]) for e in table["fields"][0]["tracks"][0]["frames"]]
drawings = {row["drawing"] for row in csv.DictReader(open(sys.argv[2], encoding="utf-8"))}
assert [v for _, v in cells] == [str(k + 1) for k in range(len(drawings))] + ["SYMBOL_NULL_CELL"], cells
frames = [f for f, _ in cells]
assert frames[0] == 0 and frames == sorted(set(frames)) and frames[-1] == 37, frames
PY
expect_error 2 '--xdts: the exposure sheet is per animation; name one with --animation (this run retimes 2)' \
  "$client_bin" curves "$data/hero-3.8.json" -o "$work/never.json" --xdts "$work/never.xdts" --server "$target"
# The report draws each bone value before and after; the sheet has one row per frame.
for id in torso/rotate torso/translate.y head/shear.x arm/scale.y 'hero-3.8.json (walk)'; do
  grep -qF "$id" "$work/walk.html" || fail "the report lacks $id"
done
[ "$(wc -l <"$work/walk.csv")" = 47 ] || fail "walk sheet: $(wc -l <"$work/walk.csv") lines, want 46 frames + header"
expect_error 2 '--report: the report is per animation; name one with --animation (this run retimes 2)' \
  "$client_bin" curves "$data/hero-3.8.json" -o "$work/never.json" --report "$work/never.html" --server "$target"
"$python" - "$here" "$data/hero-3.8.json" "$work/walk.json" "$work/hero-3.8.anime.json" <<'PY' || fail "hero-3.8: --animation / 8 drawings a second"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval
before, walk, every = (json.load(open(p)) for p in sys.argv[2:5])
spine_eval.check(before, walk, ["walk"])
assert walk["animations"]["idle"] == before["animations"]["idle"], "idle was not named"
assert walk["animations"]["blink"] == before["animations"]["blink"]
for key in ("skeleton", "bones", "slots", "skins", "events", "koma_unknown_top"):
    assert walk[key] == before[key], key
for key in ("slots", "events", "drawOrder"):
    assert walk["animations"]["walk"][key] == before["animations"]["walk"][key], key
assert spine_eval.drawings_in(every, "idle", "head/rotate", 0, 1) == 8
assert spine_eval.drawings_in(every, "idle", "head/rotate", 1, 2) == 8
print("--animation and 8 drawings a second: ok")
PY

# On twos the drawings follow the same rule with two grid frames each.
"$client_bin" curves "$data/hero-4.2.json" -o "$work/twos.json" --on 2 --server "$target" \
  >/dev/null || fail "--on 2 failed"
"$python" - "$here" "$data/hero-4.2.json" "$work/twos.json" <<'PY' || fail "hero-4.2 on twos"
import json, sys
sys.path.insert(0, sys.argv[1])
import spine_eval
before, after = (json.load(open(p)) for p in sys.argv[2:4])
print("on twos:", spine_eval.check(before, after, ["walk"], on=2), "values checked")
PY

# A kept timing group (--group-mode NAME=keep): its timelines are written back as they came
# (they were once written as one key at 0 s), the other bones retimed.
"$client_bin" curves "$data/hero-4.1.json" -o "$work/kept.json" --animation walk \
  --group 'trunk=torso/*' --group-mode trunk=keep --server "$target" >/dev/null ||
  fail "--group-mode trunk=keep failed"
"$python" - "$data/hero-4.1.json" "$work/kept.json" <<'PY' || fail "a kept group's timelines changed"
import json, sys
before, after = (json.load(open(p))["animations"]["walk"]["bones"] for p in sys.argv[1:3])
assert after["torso"] == before["torso"], after["torso"]
assert after["head"] != before["head"], "head was not retimed"
PY

# koma batch: one animation per skeleton (named, or the only one with bone keys), the same
# bytes as the single command.
"$client_bin" curves "$data/matt-3.7.json" -o "$work/matt-walk.json" --animation walk \
  --server "$target" >/dev/null || fail "matt --animation walk failed"
"$client_bin" batch curves "$data/matt-3.7.json" "$data/hero-3.8.json" -o "$work/batch" \
  --animation walk --server "$target" >"$work/batch.txt" 2>&1 || fail "koma batch: $(cat "$work/batch.txt")"
cmp "$work/batch/matt-3.7.json" "$work/matt-walk.json" || fail "batch matt differs from the CLI"
cmp "$work/batch/hero-3.8.json" "$work/walk.json" || fail "batch hero-3.8 differs from the CLI"
# A folder with --animation: its skeletons (*.json) are the inputs, the same bytes; a
# motion3.json among them is refused by name (--animation takes skeletons only).
mkdir -p "$work/skeletons/sub"
cp "$data/matt-3.7.json" "$work/skeletons/"
cp "$data/hero-3.8.json" "$work/skeletons/sub/"
"$client_bin" batch curves "$work/skeletons" -o "$work/batch_folder" --animation walk \
  --server "$target" >"$work/batch_folder.txt" 2>&1 ||
  fail "koma batch FOLDER --animation: $(cat "$work/batch_folder.txt")"
cmp "$work/batch_folder/matt-3.7.json" "$work/matt-walk.json" || fail "folder batch matt differs"
cmp "$work/batch_folder/sub/hero-3.8.json" "$work/walk.json" || fail "folder batch hero differs"
printf '{"Version": 3, "Meta": {"Duration": 1, "Fps": 30}, "Curves": []}' \
  >"$work/skeletons/arm.motion3.json"
expect_exit 1 "$work/batch-folder-err.txt" "$client_bin" batch curves "$work/skeletons" \
  -o "$work/batch_folder2" --animation walk --server "$target"
grep -q "animation: $work/skeletons/arm.motion3.json is not a Spine skeleton" \
  "$work/batch-folder-err.txt" || fail "motion3 with --animation: $(cat "$work/batch-folder-err.txt")"
expect_exit 1 "$work/batch-err.txt" "$client_bin" batch curves "$data/hero-3.8.json" \
  -o "$work/batch2" --server "$target"
grep -q 'one animation per skeleton here; this one has 2 with bone keys ("walk", "idle")' \
  "$work/batch-err.txt" "$work/batch2"/* 2>/dev/null || fail "batch without --animation: $(cat "$work/batch-err.txt")"

# Errors: a bad file names the JSON path, an unknown animation the ones there are, and .skel is
# refused as binary. Exit 1, nothing written.
sed 's/"angle": 20, "curve": "stepped"/"angle": 20, "curve": "smooth"/' "$data/hero-3.8.json" \
  >"$work/bad.json"
expect_error 1 'bad.json (Spine JSON): animations.walk.bones.torso.rotate\[1\].curve: unknown curve kind "smooth"' \
  "$client_bin" curves "$work/bad.json" -o "$work/never.json" --server "$target"
[ ! -e "$work/never.json" ] || fail "a file was written for a bad skeleton"
expect_error 1 'no animation named "run" (the skeleton has "walk", "idle", "blink")' \
  "$client_bin" curves "$data/hero-3.8.json" -o "$work/never.json" --animation run --server "$target"
printf '\x1b\x00kOmA' >"$work/hero.skel"
expect_error 1 'hero.skel is a binary Spine skeleton' \
  "$client_bin" curves "$work/hero.skel" -o "$work/never.json" --server "$target"
expect_error 2 'a Spine skeleton is written back as Spine JSON' \
  "$client_bin" curves "$data/hero-3.8.json" -o "$work/never.csv" --server "$target"

stop_server
echo "spine e2e: ok"

#!/usr/bin/env bash
# End to end: key poses merged into poses and timing groups (docs/semantics.md, "Key poses",
# "Timing groups") through the real koma_server on a free loopback port and the real
# `koma curves`, on generated motion3.json files keyed like Cubism animators key them (40-80
# curves at staggered times, blinks, a talking mouth; tests/testing/live2d_motion.h), at 30 and
# 60 fps. Usage: curves_groups_e2e_test.sh KOMA_SERVER KOMA MAKE_LIVE2D_MOTION
set -euo pipefail
server_bin=$1 client_bin=$2 make_motion=$3

source "$(dirname "$0")/lib.sh"

start_server "$server_bin"

# check_runs IN OUT N [IDS_ON_N2 N2] [--some-shorter]: in OUT (a stepped motion3.json), every
# curve that moves in IN shows no drawing (run of one value) shorter than N grid frames of
# 24 fps but the clip's last, and at most (grid frames - 1) / N + 1 drawings; curves whose id
# starts with a prefix in IDS_ON_N2 (comma-separated) with N2 instead, and at least one of them
# shows an N2-frame drawing. --some-shorter instead asserts some drawing IS shorter than N.
check_runs() {
  python3 - "$@" <<'PY'
import json, sys
args = sys.argv[1:]
some_shorter = "--some-shorter" in args
# --lipblink: the default face group's mouth and eyes are LipBlink's drawings (mouth holds and
# blinks of 1-3 frames, paper Eq. 7), not koma-uchi: checked against `koma lipblink` below.
skip = {"ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"} if "--lipblink" in args else set()
args = [a for a in args if a not in ("--some-shorter", "--lipblink")]
before, after = (json.load(open(p)) for p in args[:2])
n = int(args[2])
prefixes = args[3].split(",") if len(args) > 3 else []
n2 = int(args[4]) if len(args) > 4 else n
duration = after["Meta"]["Duration"]
last_grid = int(duration * 24 + 1e-9)
def values(s):  # the start, every segment's end and the Bezier handles' values
    out, i = [s[1]], 2
    while i < len(s):
        if s[i] == 1:
            out += [s[i + 2], s[i + 4], s[i + 6]]
            i += 7
        else:
            out.append(s[i + 2])
            i += 3
    return out
shortest_seen, n2_seen, checked = 10**9, False, 0
for b, a in zip(before["Curves"], after["Curves"]):
    assert b["Id"] == a["Id"]
    if min(values(b["Segments"])) == max(values(b["Segments"])) or a["Id"] in skip:
        continue
    s = a["Segments"]
    points = [(s[0], s[1])] + [(s[i + 1], s[i + 2]) for i in range(2, len(s), 3)]
    assert all(s[i] == 2 for i in range(2, len(s), 3)), a["Id"]
    changes = [round(points[0][0] * 24)]
    for (t0, v0), (t1, v1) in zip(points, points[1:]):
        if v1 != v0:
            changes.append(round(t1 * 24))
    runs = [e - b for b, e in zip(changes, changes[1:] + [last_grid + 1])]
    want = n2 if any(a["Id"].startswith(p) for p in prefixes) else n
    checked += 1
    if some_shorter:
        shortest_seen = min(shortest_seen, min(runs[:-1] or [10**9]))
        continue
    assert all(r >= want for r in runs[:-1]), (a["Id"], want, runs)
    assert len(runs) <= last_grid // want + 1, (a["Id"], len(runs), last_grid)
    n2_seen = n2_seen or (want == n2 and n2 != n and n2 in runs[:-1])
if some_shorter:
    assert shortest_seen < n, ("no drawing shorter than", n, shortest_seen)
elif prefixes:
    assert n2_seen, ("no curve of", prefixes, "shows a", n2, "frame drawing")
assert checked >= 30, checked
print(f"{checked} moving curves checked (on {n}s{', ' + args[3] + ' on ' + str(n2) + 's' if prefixes else ''})")
PY
}

for fps in 30 60; do
  for curves in 40 80; do
    m="$work/m${fps}_${curves}.motion3.json"
    "$make_motion" "$fps" "$curves" 5 "$((fps + curves))" >"$m" || fail "make_live2d_motion"
    # The default: merged key poses, Live2D's default groups (face, hair, body), on threes.
    "$client_bin" curves "$m" -o "$work/three.motion3.json" --timing "$work/sheet.csv" \
      --server "$target" >"$work/summary.txt" || fail "koma curves $m failed"
    check_runs "$m" "$work/three.motion3.json" 3 --lipblink || fail "$m on threes"
    head -1 "$work/sheet.csv" | grep -qx \
      'output_frame,drawing,source_frame,time_s,face_drawing,face_source_frame,hair_drawing,hair_source_frame,keys' \
      || fail "sheet: not one track per group: $(head -1 "$work/sheet.csv")"
    # On twos, and the hair on twos while the rest is on threes.
    "$client_bin" curves "$m" -o "$work/two.motion3.json" --on 2 --server "$target" >/dev/null \
      || fail "koma curves --on 2 failed"
    check_runs "$m" "$work/two.motion3.json" 2 --lipblink || fail "$m on twos"
    "$client_bin" curves "$m" -o "$work/hair.motion3.json" --group-on hair=2 \
      --server "$target" >/dev/null || fail "koma curves --group-on hair=2 failed"
    check_runs "$m" "$work/hair.motion3.json" 3 ParamHair,ParamBust 2 --lipblink \
      || fail "$m hair on twos"
    # Every keyframe time a key pose, one group: the problem the merging solves.
    "$client_bin" curves "$m" -o "$work/unmerged.motion3.json" --no-merge-keys \
      --no-default-groups --server "$target" >/dev/null || fail "koma curves --no-merge-keys"
    check_runs "$m" "$work/unmerged.motion3.json" 3 --some-shorter || fail "$m unmerged"
  done
done
cat "$work/summary.txt"
grep -q "timing groups: body " "$work/summary.txt" || fail "summary: no timing groups line"
grep -q "key poses ([0-9]*, [0-9]* merged from [0-9]* keyframe times)" "$work/summary.txt" \
  || fail "summary: no merged key poses"

# Groups from the config file ([curves] group = [...]), as if typed.
cat >"$work/koma.toml" <<'TOML'
[curves]
group = ["arms=ParamArm*,ParamHand*:on=2", "face=ParamEye*,ParamMouth*,ParamBrow*"]
TOML
"$client_bin" --config "$work/koma.toml" curves "$m" -o "$work/cfg.motion3.json" \
  --timing "$work/cfg.csv" --server "$target" >/dev/null || fail "koma curves --config failed"
head -1 "$work/cfg.csv" | grep -q ',arms_drawing,arms_source_frame,face_drawing,' \
  || fail "config groups not used: $(head -1 "$work/cfg.csv")"
check_runs "$m" "$work/cfg.motion3.json" 3 ParamArm,ParamHand 2 || fail "config groups' timing"

# Bad groups: a usage error (exit 2) for a malformed flag, the server's error (exit 1) naming
# the field for a bad group.
expect_exit 2 "$work/err.txt" "$client_bin" curves "$m" -o "$work/x.motion3.json" \
  --group hair --server "$target"
grep -q -- "--group: \"hair\" is not NAME=ID" "$work/err.txt" || fail "--group usage: $(cat "$work/err.txt")"
expect_exit 2 "$work/err.txt" "$client_bin" curves "$m" -o "$work/x.motion3.json" \
  --group-on tail=2 --server "$target"
grep -q 'no timing group "tail" (groups: face, hair)' "$work/err.txt" \
  || fail "--group-on usage: $(cat "$work/err.txt")"
expect_error 1 'INVALID_ARGUMENT: timing_groups\[1\].name: "a" is already' \
  "$client_bin" curves "$m" -o "$work/x.motion3.json" --group 'a=ParamArm*' --group 'a=ParamHair*' \
  --server "$target"
[ ! -e "$work/x.motion3.json" ] || fail "a failed call wrote an output file"

# Group modes (docs/semantics.md, "Group modes") on the samples. The default groups: one call
# gives the whole anime motion, the mouth and eyes exactly as `koma lipblink` draws them (its
# file's Segments), each eye curve with three values, the body stepped.
samples="$(cd "$(dirname "$0")/../.." && pwd)/samples"
talk="$samples/talk_blink.motion3.json"
"$client_bin" curves "$talk" -o "$work/talk_anime.motion3.json" --on 3 --json \
  --report "$work/talk.html" --server "$target" >"$work/talk.json" || fail "koma curves $talk"
"$client_bin" lipblink "$talk" -o "$work/talk_lip.motion3.json" --server "$target" >/dev/null \
  || fail "koma lipblink $talk"
python3 - "$talk" "$work/talk_anime.motion3.json" "$work/talk_lip.motion3.json" "$work/talk.json" <<'PY' \
  || fail "talk_blink: the default face group is not LipBlink's drawing"
import json, sys
src, anime, lip, summary = (json.load(open(p)) for p in sys.argv[1:5])
by_id = lambda m: {c["Id"]: c["Segments"] for c in m["Curves"]}
src, anime, lip = by_id(src), by_id(anime), by_id(lip)
for i in ("ParamMouthOpenY", "ParamEyeLOpen", "ParamEyeROpen"):
    assert anime[i] == lip[i], (i, anime[i][:20], lip[i][:20])
    s = anime[i]
    assert all(s[k] == 2 for k in range(2, len(s), 3)), i
    shown = {s[1]} | {s[k + 2] for k in range(2, len(s), 3)}
    assert len(shown) <= 3 or i == "ParamMouthOpenY", (i, sorted(shown))
assert anime["ParamAngleX"] != src["ParamAngleX"] and anime["ParamAngleX"] != lip["ParamAngleX"]
modes = {g["name"]: g["mode"] for g in summary["timing_groups"]}
assert modes == {"body": "step", "face": "lipblink", "hair": "step"}, modes
print("talk_blink: mouth and eyes as koma lipblink draws them; groups", modes)
PY
grep -q '"mode":"lipblink"' "$work/talk.html" || fail "report: no group mode"
# --group-mode face=keep: the face's keyframes untouched; a group's mode from --group.
"$client_bin" curves "$talk" -o "$work/talk_keep.motion3.json" --group-mode face=keep \
  --timing "$work/talk_keep.csv" --server "$target" >"$work/keep.txt" || fail "--group-mode keep"
grep -q "face (3 curves, kept as they are)" "$work/keep.txt" || fail "summary: $(cat "$work/keep.txt")"
head -1 "$work/talk_keep.csv" | grep -qx 'output_frame,drawing,source_frame,time_s,keys' \
  || fail "a kept group has a sheet track: $(head -1 "$work/talk_keep.csv")"
python3 - "$talk" "$work/talk_keep.motion3.json" <<'PY' || fail "kept face changed"
import json, sys
src, out = (json.load(open(p)) for p in sys.argv[1:3])
for a, b in zip(src["Curves"], out["Curves"]):
    assert (a["Segments"] == b["Segments"]) == (a["Id"] != "ParamAngleX"), a["Id"]
PY
"$client_bin" curves "$talk" -o "$work/talk_eyes.csv" --group 'eyes=ParamEye*:mode=lipblink,on=2' \
  --group 'mouth=ParamMouth*:mode=keep' --server "$target" >"$work/eyes.txt" || fail "--group mode="
grep -q "eyes (2 curves, lipblink, the rest on twos" "$work/eyes.txt" || fail "summary: $(cat "$work/eyes.txt")"
# arm_head has no face curves: the default groups step everything, as before.
"$client_bin" curves "$samples/arm_head.motion3.json" -o "$work/arm.motion3.json" \
  --server "$target" >/dev/null || fail "koma curves arm_head"
expect_exit 2 "$work/err.txt" "$client_bin" curves "$talk" -o "$work/x.motion3.json" \
  --group-mode face=squash --server "$target"
grep -q -- '--group-mode face: "squash" is not a group mode (step, keep or lipblink)' "$work/err.txt" \
  || fail "--group-mode usage: $(cat "$work/err.txt")"

stop_server
echo "PASS: curves key poses, timing groups and group modes end to end"

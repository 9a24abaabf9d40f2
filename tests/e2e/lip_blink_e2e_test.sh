#!/usr/bin/env bash
# End to end: the real koma_server on a free loopback port, the real `koma lipblink` on the
# bundled talking-and-blinking sample, then CSV. Usage: lip_blink_e2e_test.sh KOMA_SERVER KOMA SAMPLE
set -euo pipefail
server_bin=$1 client_bin=$2 sample=$3

source "$(dirname "$0")/lib.sh"

start_server "$server_bin"

# Counted in the motion's own 30 fps frames (--timing-fps 0): frame numbers of the source.
"$client_bin" lipblink "$sample" -o "$work/source.motion3.json" --seed 7 --timing-fps 0 \
  --server "$target" >"$work/summary.txt" || fail "koma lipblink --timing-fps 0 failed"
cat "$work/summary.txt"
grep -q "mouth ParamMouthOpenY: speech at frames 12-50, 68-104" "$work/summary.txt" \
  || fail "summary: speech intervals"
grep -q "eye ParamEyeLOpen: 2 blinks: frame 31 (hold 2), frame 92 (hold 3)" "$work/summary.txt" \
  || fail "summary: left eye blinks"
grep -q "eye ParamEyeROpen: 2 blinks: frame 31 (hold 2), frame 92 (hold 3)" "$work/summary.txt" \
  || fail "summary: right eye blinks (linked)"

# The default: the 24 fps film grid. The same speech, in grid frames (12/30 s = grid 9.6,
# 51/30 s = grid 40.8), holds of 3 grid frames = 1/8 s, each starting at an exact grid time.
"$client_bin" lipblink "$sample" -o "$work/out.motion3.json" --seed 7 --server "$target" \
  >"$work/summary.txt" || fail "koma lipblink failed"
cat "$work/summary.txt"
grep -q "on the 24 fps film grid" "$work/summary.txt" || fail "summary: no film grid line"
grep -q "mouth ParamMouthOpenY: speech at grid frames 9-40 (0.38-1.71 s), 54-84" \
  "$work/summary.txt" || fail "summary: speech intervals on the grid"
python3 - "$work/out.motion3.json" <<'PY' || fail "mouth drawings are not on the 24 fps grid"
import json, sys
curves = {c["Id"]: c for c in json.load(open(sys.argv[1]))["Curves"]}
s = curves["ParamMouthOpenY"]["Segments"]
times = [s[0]] + [s[i + 1] for i in range(2, len(s), 3)]
inside = [t for t in times if 0.3 < t < 1.7]  # the first speech interval
assert inside, times
for t in inside:
    assert abs(t * 24 - round(t * 24)) < 1e-9, ("not on the grid", t)
gaps = [round((b - a) * 24) for a, b in zip(inside, inside[1:])]
assert all(1 <= g <= 3 for g in gaps) and gaps.count(3) >= len(gaps) - 1, gaps
print("mouth holds on the grid:", gaps)
PY

# Same seed, same file; valid motion3 with recounted Meta; ParamAngleX untouched.
"$client_bin" lipblink "$sample" -o "$work/again.motion3.json" --seed 7 --server "$target" \
  >/dev/null || fail "second run failed"
cmp -s "$work/out.motion3.json" "$work/again.motion3.json" || fail "same seed, different files"
python3 - "$sample" "$work/out.motion3.json" <<'PY' || fail "written motion3.json is wrong"
import json, sys
before, after = (json.load(open(p)) for p in sys.argv[1:3])
curves = {c["Id"]: c for c in after["Curves"]}
assert curves["ParamAngleX"] == before["Curves"][3], "ParamAngleX changed"
points = segments = 0
for c in after["Curves"]:
    s = c["Segments"]
    points += 1
    i = 2
    while i < len(s):
        kind = s[i]
        step = 7 if kind == 1 else 3
        segments += 1
        points += 3 if kind == 1 else 1
        i += step
    assert i == len(s), c["Id"]
meta = after["Meta"]
assert meta["TotalSegmentCount"] == segments and meta["TotalPointCount"] == points, meta
mouth = curves["ParamMouthOpenY"]["Segments"]
values = set(mouth[1::3])  # first value, then every segment's end value (all stepped)
assert len(values) <= 3, values
print("motion3.json checks passed")
PY

# CSV in and out, FOLLOW mode.
printf 'frame,ParamMouthOpenY,Other\n' >"$work/in.csv"
for f in $(seq 0 29); do
  if [ "$f" -ge 5 ] && [ "$f" -lt 25 ]; then v=$(( (f * 3) % 5 )); else v=0; fi
  echo "$f,0.$((v * 2)),$f" >>"$work/in.csv"
done
"$client_bin" lipblink "$work/in.csv" -o "$work/out.csv" --mode follow --on 2 --server "$target" \
  >/dev/null || fail "CSV lipblink failed"
[ "$(wc -l <"$work/out.csv")" = 31 ] || fail "CSV output has $(wc -l <"$work/out.csv") lines"
cut -d, -f3 "$work/out.csv" | tail -n +2 | tr '\n' ' ' | grep -q "^0 1 2 3 4 5 " \
  || fail "the other CSV curve changed"

# A bad parameter: the server's code and message, exit 1.
expect_error 1 'INVALID_ARGUMENT: mouth.ids\[0\]: "ParamMouth" is not a curve' \
  "$client_bin" lipblink "$sample" -o "$work/bad.motion3.json" --mouth ParamMouth --server "$target"

stop_server
echo "PASS: lipblink end to end"

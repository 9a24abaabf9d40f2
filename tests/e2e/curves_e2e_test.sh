#!/usr/bin/env bash
# End to end: the real koma_server on a free loopback port, the real `koma curves` on the
# bundled motion3.json sample, then on CSV. Usage: curves_e2e_test.sh KOMA_SERVER KOMA SAMPLE
set -euo pipefail
server_bin=$1 client_bin=$2 sample=$3

source "$(dirname "$0")/lib.sh"

start_server "$server_bin"

# motion3.json in and out, on threes with the arm on twos, tame and tsume.
"$client_bin" curves "$sample" -o "$work/out.motion3.json" --tame 1.5 --tsume 1.5 \
  --curve-on ParamArmRA=2 --timing "$work/sheet.csv" --server "$target" >"$work/summary.txt" \
  || fail "koma curves failed"
cat "$work/summary.txt"
grep -q "on threes: .* for ParamAngleX" "$work/summary.txt" || fail "summary: no 'on threes'"
grep -q "on twos: .* for ParamArmRA" "$work/summary.txt" || fail "summary: no 'on twos'"
head -1 "$work/sheet.csv" | grep -q "^output_frame,drawing,source_frame" || fail "sheet header"

# The written file: valid JSON, every curve stepped, Meta counts equal a recount, and the
# fields koma does not touch unchanged.
python3 - "$sample" "$work/out.motion3.json" <<'PY' || fail "written motion3.json is wrong"
import json, sys
before, after = (json.load(open(p)) for p in sys.argv[1:3])
points = segments = 0
for curve in after["Curves"]:
    s = curve["Segments"]
    points += 1
    i = 2
    while i < len(s):
        assert s[i] == 2, ("not stepped", curve["Id"], s[i])
        segments += 1
        points += 1
        i += 3
    assert i == len(s), curve["Id"]
meta = after["Meta"]
assert meta["CurveCount"] == len(after["Curves"]) == len(before["Curves"])
assert meta["TotalSegmentCount"] == segments, (meta["TotalSegmentCount"], segments)
assert meta["TotalPointCount"] == points, (meta["TotalPointCount"], points)
for key in ("Duration", "Fps", "Loop", "FadeInTime", "FadeOutTime", "UserDataCount"):
    assert meta[key] == before["Meta"][key], key
assert after["UserData"] == before["UserData"]
assert after["Version"] == before["Version"]
for b, a in zip(before["Curves"], after["Curves"]):
    assert (b["Id"], b["Target"]) == (a["Id"], a["Target"])
    assert b.get("FadeInTime") == a.get("FadeInTime")
print("motion3.json checks passed")
PY

# Every key is drawn (issue 40): the sample's keys, measured by --check-keys, and each drawing
# that carries keys named in the sheet's keys column and the XDTS's key track.
"$client_bin" curves "$sample" -o "$work/keys.motion3.json" --check-keys --json \
  --timing "$work/keys.csv" --xdts "$work/keys.xdts" --server "$target" >"$work/keys.json" \
  || fail "koma curves --check-keys failed"
python3 - "$work/keys.json" "$work/keys.csv" "$work/keys.xdts" <<'PY' || fail "keys are not drawn"
import csv, json, sys
summary = json.load(open(sys.argv[1]))
check = summary["key_check"]
assert check["ends_missed"] == 0, check
assert check["extremes"] > 0 and check["extremes_missed"] <= summary["keys_shared"], check
named = [row["keys"] for row in csv.DictReader(open(sys.argv[2])) if row["keys"]]
assert named, "no drawing sheet row names a key"
xdts = json.loads(open(sys.argv[3], encoding="utf-8").read().partition("\n")[2])
table = xdts["timeTables"][0]
dialog = [f for f in table["fields"] if f["fieldId"] == 3]
assert dialog, "no key track in the XDTS"
headers = [h for h in table["timeTableHeaders"] if h["fieldId"] == 3][0]["names"]
assert all(name.endswith(" keys") for name in headers), headers
print("keys:", summary["keys_drawn"], "drawn,", summary["keys_shared"], "shared;", check)
PY

# The retimed file reads back: retime it again.
"$client_bin" curves "$work/out.motion3.json" -o "$work/again.motion3.json" \
  --server "$target" >/dev/null || fail "the written motion3.json does not read back"

# CSV in and out.
printf 'frame,ParamA\n' >"$work/in.csv"
for f in $(seq 0 30); do echo "$f,$((f * 2))" >>"$work/in.csv"; done
"$client_bin" curves "$work/in.csv" -o "$work/out.csv" --on 2 --fps 24 --server "$target" \
  >/dev/null || fail "CSV retime failed"
[ "$(wc -l <"$work/out.csv")" = 32 ] || fail "CSV output has $(wc -l <"$work/out.csv") lines"
sed -n 2,4p "$work/out.csv" | cut -d, -f2 | tr '\n' ' ' | grep -q "^0 0 " \
  || fail "CSV output is not on twos: $(sed -n 2,4p "$work/out.csv")"

# A bad parameter: the server's code and message, exit 1, no output written.
expect_error 1 "INVALID_ARGUMENT: key_frames\[2\]: 20" \
  "$client_bin" curves "$sample" -o "$work/bad.motion3.json" --keys 0,30,20 --server "$target"
[ ! -e "$work/bad.motion3.json" ] || fail "a failed call wrote an output file"

# A drawing sheet that cannot be written is refused before the call (the server given cannot
# be reached), and the motion3.json is not written either.
expect_error 1 "^koma: cannot write $work/missing/s.csv" "$client_bin" curves "$sample" \
  -o "$work/early.motion3.json" --timing "$work/missing/s.csv" --server 127.0.0.1:1
[ ! -e "$work/early.motion3.json" ] || fail "an unwritable --timing still wrote the curves"

# A malformed --curve-on: usage error, exit 2.
expect_exit 2 "$work/err.txt" \
  "$client_bin" curves "$sample" -o "$work/x.motion3.json" --curve-on ParamArmRA --server "$target"

stop_server
echo "PASS: curves end to end"

#!/usr/bin/env bash
# End to end (issues 28, 41): RetimeSkeletal on real takes through the real koma_server on a
# free loopback port and the real koma client: clips made from a real BVH (a T-pose prepended,
# two takes, a glitch frame, a 40 s take, the take at 60 and 120 fps), the cuts in the summary,
# --json and the report, the anime defaults with no flags (on twos or threes, omissions that
# scale with the take), --preset paper, the omission rate, and --preset twos / threes giving
# median holds of 2 and 3 grid frames on every real clip and sample.
# Usage: real_takes_e2e_test.sh KOMA_SERVER KOMA TESTDATA_DIR SAMPLES_DIR
set -euo pipefail
server_bin=$1 client_bin=$2 testdata=$3 samples=$4

source "$(dirname "$0")/lib.sh"

start_server "$server_bin" --worker_threads=2
python3 "$(dirname "$0")/make_real_takes.py" "$testdata/bvh_test1.bvh" "$work"

# field FILE KEY: a field of a --json summary, as JSON.
field() { python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))[sys.argv[2]]))' "$1" "$2"; }
# first_frame FILE.bvh: the first motion line's numbers, as floats.
first_frame() { python3 -c '
import sys
lines = open(sys.argv[1]).read().split("MOTION")[1].strip().splitlines()
print([float(v) for v in lines[2].split()])' "$1"; }

# The T-pose first frame: one cut before frame 1, named in the summary, --json and the report;
# the calibration frame comes out as it went in.
"$client_bin" skeletal "$work/tpose.bvh" -o "$work/tpose_anime.bvh" --server "$target" \
  >"$work/tpose.txt" || fail "koma skeletal tpose.bvh failed"
cat "$work/tpose.txt"
grep -q "cuts         1; shots retimed separately start at source frames 0, 1" "$work/tpose.txt" \
  || fail "the summary does not name the cut"
"$client_bin" skeletal "$work/tpose.bvh" -o "$work/tpose_anime.bvh" --server "$target" \
  --json --report "$work/tpose.html" >"$work/tpose.json" || fail "--json --report failed"
[ "$(field "$work/tpose.json" cut_frames)" = "[1]" ] || fail "cut_frames: $(field "$work/tpose.json" cut_frames)"
grep -q '"cuts":\[1\]' "$work/tpose.html" || fail "the report carries no cuts"
[ "$(first_frame "$work/tpose.bvh")" = "$(first_frame "$work/tpose_anime.bvh")" ] \
  || fail "the calibration frame changed"
python3 - "$work/tpose.json" <<'PY' || fail "omissions next to the cut"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["omissions_applied"] >= 2, s  # 2.5 s at the default rate of 1 a second
assert all(d not in (0, 1) for d in s["deleted_frames"]), s["deleted_frames"]
PY

# Two takes and a glitch frame: their cuts.
"$client_bin" skeletal "$work/two_takes.bvh" -o "$work/two.bvh" --server "$target" --json \
  >"$work/two.json" || fail "two_takes failed"
[ "$(field "$work/two.json" cut_frames)" = "[45]" ] || fail "two takes: $(field "$work/two.json" cut_frames)"
"$client_bin" skeletal "$work/glitch.bvh" -o "$work/glitch_anime.bvh" --server "$target" --json \
  >"$work/glitch.json" || fail "glitch failed"
[ "$(field "$work/glitch.json" cut_frames)" = "[37, 38]" ] \
  || fail "glitch: $(field "$work/glitch.json" cut_frames)"

# The 40 s take: no cut; the default rate scales with the length (40 s: 40 omissions), the
# paper's count is one flag away (--preset paper: 4); --omit and --omissions-per-second together
# are a usage error.
"$client_bin" skeletal "$work/long.bvh" -o "$work/long_anime.bvh" --server "$target" --json \
  >"$work/long.json" || fail "long take failed"
[ "$(field "$work/long.json" cut_frames)" = "[]" ] || fail "the long take has cuts"
[ "$(field "$work/long.json" omissions_applied)" = 40 ] \
  || fail "40 s at the default 1 a second: $(field "$work/long.json" omissions_applied) omissions"
"$client_bin" skeletal "$work/long.bvh" -o "$work/long_paper.bvh" --server "$target" \
  --preset paper >"$work/long_paper.txt" || fail "--preset paper failed"
grep -q "requested omissions 4, holds 320, max_hold 3 grid frames" "$work/long_paper.txt" \
  || fail "--preset paper: $(cat "$work/long_paper.txt")"
grep -q "asked for" "$work/long_paper.txt" && fail "--preset paper names rates"
"$client_bin" skeletal "$work/long.bvh" -o "$work/long_rate.bvh" --server "$target" --json \
  --omissions-per-second 1 >"$work/long_rate.json" || fail "long take with a rate failed"
cmp -s "$work/long_rate.bvh" "$work/long_anime.bvh" || fail "the default is not 1 a second"
expect_error 2 "omissions-per-second" "$client_bin" skeletal "$work/long.bvh" -o "$work/x.bvh" \
  --omit 3 --omissions-per-second 1 --server "$target"
# A preset's rate gives way to --omit on the line.
"$client_bin" skeletal "$work/long.bvh" -o "$work/snappy.bvh" --server "$target" --json \
  --preset snappy --omit 6 >"$work/snappy.json" || fail "--preset snappy --omit 6 failed"
[ "$(field "$work/snappy.json" omissions_requested)" = 6 ] || fail "--omit did not win over the preset"
"$client_bin" skeletal "$work/long.bvh" -o "$work/snappy.bvh" --server "$target" --json \
  --preset snappy >"$work/snappy.json" || fail "--preset snappy failed"
[ "$(field "$work/snappy.json" omissions_requested)" = 60 ] || fail "snappy: not 1.5 a second"

# No flags: anime timing on every take, 30 to 120 fps, 2.5 to 40 s (docs/semantics.md, "Defaults:
# anime timing"): a median hold of at least 2 grid frames, 7.5 to 12.5 drawings a second on the
# grid, at least one omission every two seconds, none at the clip's ends; the summary says so.
for clip in "$testdata"/bvh_test1.bvh "$work"/take_60.bvh "$work"/take_120.bvh \
  "$work"/long.bvh "$work"/long_120.bvh "$samples"/pitch.bvh; do
  "$client_bin" skeletal "$clip" --timing-only --timing "$work/sheet.csv" --output-rate timing \
    --server "$target" --json >"$work/defaults.json" 2>"$work/defaults.txt" \
    || fail "$clip with no flags"
  grep -q "; asked for 8 drawings and 1 omission a second (the anime defaults" \
    "$work/defaults.txt" || fail "$clip: the summary does not name the defaults"
  python3 - "$work/sheet.csv" "$work/defaults.json" "$clip" <<'PY' || fail "$clip: not anime timing"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
summary = json.load(open(sys.argv[2]))
runs = []
for i, row in enumerate(rows):
    if i == 0 or row["source_frame"] != rows[i - 1]["source_frame"]:
        runs.append(0)
    runs[-1] += 1
seconds = len(rows) / 24
runs.sort()
print(f"{sys.argv[3]}: {seconds:.1f} s, {len(runs) / seconds:.2f} drawings a second, median "
      f"hold {runs[(len(runs) - 1) // 2]}, {summary['omissions_applied']} omissions")
assert runs[(len(runs) - 1) // 2] >= 2, runs
assert 7.5 <= len(runs) / seconds <= 12.5, len(runs) / seconds
assert summary["omissions_applied"] >= 0.5 * seconds, summary
assert all(0 < d < summary["input_frames"] - 1 for d in summary["deleted_frames"]), summary
assert summary["drawings_per_second"] == 8 and summary["omissions_per_second"] == 1, summary
assert abs(summary["drawings_shown_per_second"] - len(runs) / seconds) < 1e-3, summary
PY
done

# Presets: the median hold on the grid (one output frame per grid frame) is 2 on twos and 3 on
# threes, on every real clip and sample.
for clip in "$testdata"/bvh_test1.bvh "$testdata"/bvh_test2.bvh "$testdata"/bvh_test3.bvh \
  "$samples"/pitch.bvh "$samples"/mocap_120fps.bvh "$work"/tpose.bvh "$work"/two_takes.bvh \
  "$work"/long.bvh; do
  for preset in twos:2 threes:3; do
    "$client_bin" skeletal "$clip" --timing-only --timing "$work/sheet.csv" --output-rate timing \
      --preset "${preset%:*}" --server "$target" >/dev/null || fail "$clip --preset ${preset%:*}"
    median=$(python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
runs = []
for i, row in enumerate(rows):
    if i == 0 or row["source_frame"] != rows[i - 1]["source_frame"]:
        runs.append(0)
    runs[-1] += 1
runs.sort()
print(runs[(len(runs) - 1) // 2], runs[len(runs) // 2])' "$work/sheet.csv")
    [ "$median" = "${preset#*:} ${preset#*:}" ] \
      || fail "$clip --preset ${preset%:*}: median hold $median grid frames"
  done
done

# A BVH with one more row than its "Frames:" line says (as assimp's Boxing_Toes test file): read
# whole, as Blender reads it, with the warning in the summary, --json, the report and, when the
# server reads the file (--send-file), its log. A partial extra row is still refused.
python3 - "$testdata/bvh_test1.bvh" "$work/extra_row.bvh" "$work/partial_row.bvh" <<'PY'
import sys
text = open(sys.argv[1]).read().replace("\r\n", "\n").rstrip("\n")
last = text.rsplit("\n", 1)[1]
open(sys.argv[2], "w").write(text + "\n" + last + "\n")
open(sys.argv[3], "w").write(text + "\n" + " ".join(last.split()[:5]) + "\n")
PY
lines=$(wc -l <"$work/extra_row.bvh")
frames_line=$(grep -n "^Frames:" "$work/extra_row.bvh" | cut -d: -f1)
warning="$work/extra_row.bvh (BVH): line $lines: \"Frames: 75\" (line $frames_line) but 76 frames follow; read all 76, as Blender does"
for how in "" --send-file; do
  "$client_bin" skeletal "$work/extra_row.bvh" -o "$work/extra_anime.bvh" --server "$target" \
    --json --report "$work/extra.html" $how >"$work/extra.json" 2>"$work/extra.txt" \
    || fail "the extra row was refused ($how): $(cat "$work/extra.txt")"
  grep -qF "  warning    $warning" "$work/extra.txt" || fail "no warning in the summary: $(cat "$work/extra.txt")"
  [ "$(field "$work/extra.json" warnings)" = "$(python3 -c 'import json,sys; print(json.dumps([sys.argv[1]]))' "$warning")" ] \
    || fail "--json warnings: $(field "$work/extra.json" warnings)"
  [ "$(field "$work/extra.json" input_frames)" = 76 ] || fail "not 76 frames read"
  grep -qF "but 76 frames follow" "$work/extra.html" || fail "the report has no warning"
done
grep -F "bvh_text: line $lines: " "$work/server.log" | grep -q 'warning="bvh_text' \
  || fail "the server log has no warning: $(tail -3 "$work/server.log")"
expect_error 1 "line $lines: unexpected" "$client_bin" skeletal "$work/partial_row.bvh" \
  -o "$work/x.bvh" --server "$target"

stop_server
echo "real takes: ok"

#!/usr/bin/env bash
# End to end (issue 28): RetimeSkeletal on real takes through the real koma_server on a free
# loopback port and the real koma client: clips made from a real BVH (a T-pose prepended, two
# takes, a glitch frame, a 40 s take), the cuts in the summary, --json and the report, the
# omission rate, and --preset twos / threes giving median holds of 2 and 3 grid frames on every
# real clip and sample. Usage: real_takes_e2e_test.sh KOMA_SERVER KOMA TESTDATA_DIR SAMPLES_DIR
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
assert s["omissions_applied"] == 4, s
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

# The 40 s take: no cut; the default count is the paper's 4, the rate scales with the length;
# --omit and --omissions-per-second together are a usage error.
"$client_bin" skeletal "$work/long.bvh" -o "$work/long_anime.bvh" --server "$target" --json \
  >"$work/long.json" || fail "long take failed"
[ "$(field "$work/long.json" cut_frames)" = "[]" ] || fail "the long take has cuts"
[ "$(field "$work/long.json" omissions_applied)" = 4 ] || fail "long take: not 4 omissions"
"$client_bin" skeletal "$work/long.bvh" -o "$work/long_rate.bvh" --server "$target" --json \
  --omissions-per-second 1 >"$work/long_rate.json" || fail "long take with a rate failed"
[ "$(field "$work/long_rate.json" omissions_applied)" = 40 ] \
  || fail "40 s at 1 a second: $(field "$work/long_rate.json" omissions_applied) omissions"
expect_error 2 "omissions-per-second" "$client_bin" skeletal "$work/long.bvh" -o "$work/x.bvh" \
  --omit 3 --omissions-per-second 1 --server "$target"
# A preset's rate gives way to --omit on the line.
"$client_bin" skeletal "$work/long.bvh" -o "$work/snappy.bvh" --server "$target" --json \
  --preset snappy --omit 6 >"$work/snappy.json" || fail "--preset snappy --omit 6 failed"
[ "$(field "$work/snappy.json" omissions_requested)" = 6 ] || fail "--omit did not win over the preset"
"$client_bin" skeletal "$work/long.bvh" -o "$work/snappy.bvh" --server "$target" --json \
  --preset snappy >"$work/snappy.json" || fail "--preset snappy failed"
[ "$(field "$work/snappy.json" omissions_requested)" = 60 ] || fail "snappy: not 1.5 a second"

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

stop_server
echo "real takes: ok"

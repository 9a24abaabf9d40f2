#!/usr/bin/env bash
# End to end on real mocap no one here wrote (pybvh's fixtures, tests/testdata/README.md): the
# real koma_server on a free loopback port, the real koma client, 30 and 120 fps BVH files
# retimed on the 24 fps film grid (docs/semantics.md, "The film grid"). From the --timing sheet:
# every drawing is held a whole number of grid frames (in seconds, within one source frame) but the
# last, no longer than max_hold grid frames, and source frame k belongs to grid frame
# floor(k * 24 / fps); the BVH keeps its frame count and Frame Time; --output-rate timing
# writes one frame per grid frame at 1/24 s; a 24 fps clip is unchanged by the grid.
# Usage: film_grid_e2e_test.sh KOMA_SERVER KOMA BVH_30FPS BVH_120FPS BVH_24FPS
set -euo pipefail
server_bin=$1 client_bin=$2 bvh30=$3 bvh120=$4 bvh24=$5

source "$(dirname "$0")/lib.sh"

start_server "$server_bin" --worker_threads=2

header() { sed -n "s/^$2:[[:space:]]*//p" "$1" | tr -d '\r'; }

# check_sheet SHEET FRAME_TIME MAX_HOLD: the timing sheet's drawings sit on the 24 fps grid.
check_sheet() {
  awk -F, -v ft="$2" -v max_hold="$3" '
    function check_run(last,   seconds, n) {
      seconds = run * ft
      n = int(seconds * 24 + 0.5)
      if (seconds > max_hold / 24 + ft + 1e-9) {
        printf "drawing of source frame %d ending at row %d lasts %.4f s > %d grid frames + one source frame\n", src, NR - 1, seconds, max_hold
        bad = 1
      }
      if (!last && (n < 1 || seconds - n / 24 > ft + 1e-9 || n / 24 - seconds > ft + 1e-9)) {
        printf "drawing of source frame %d ending at row %d lasts %.4f s, not whole grid frames\n", src, NR - 1, seconds
        bad = 1
      }
    }
    NR == 1 {
      if ($0 != "output_frame,source_frame,kind,time_s,grid_frame") { print "header: " $0; bad = 1 }
      next
    }
    {
      k = $1 + 0
      want = int(k * 24 * ft + 1e-3)
      if ($5 + 0 != want) { printf "row %d: grid_frame %s, want %d\n", k, $5, want; bad = 1 }
      if (NR > 2 && $2 == src) { run++ } else { if (NR > 2) check_run(0); run = 1; src = $2 }
      rows++
    }
    END {
      check_run(1)
      print rows " rows"
      exit bad
    }' "$1"
}

for clip in "$bvh30" "$bvh120"; do
  name=$(basename "$clip" .bvh)
  frames=$(header "$clip" Frames)
  frame_time=$(header "$clip" "Frame Time")

  # At the source rate (the default).
  "$client_bin" skeletal "$clip" -o "$work/$name.bvh" --timing "$work/$name.csv" \
    --server "$target" --deadline 30 >"$work/$name.txt" || fail "koma skeletal $name failed"
  cat "$work/$name.txt"
  grep -q "film grid  24 fps" "$work/$name.txt" || fail "$name: the summary has no film grid line"
  [ "$(header "$work/$name.bvh" Frames)" = "$frames" ] || fail "$name: Frames changed"
  awk -v a="$(header "$work/$name.bvh" "Frame Time")" -v b="$frame_time" \
    'BEGIN { exit !(a - b < 1e-12 && b - a < 1e-12) }' || fail "$name: Frame Time changed"
  check_sheet "$work/$name.csv" "$frame_time" 3 >"$work/check.txt" \
    || fail "$name: $(cat "$work/check.txt")"
  [ "$(cat "$work/check.txt")" = "$frames rows" ] || fail "$name: $(cat "$work/check.txt")"
  grep -q ",HELD," "$work/$name.csv" || fail "$name: no HELD frame"
  # The drawings changed: fewer distinct source frames than the source's.
  shown=$(tail -n +2 "$work/$name.csv" | cut -d, -f2 | sort -un | wc -l)
  [ "$shown" -lt "$frames" ] || fail "$name: all $frames source frames still shown"

  # At the grid's rate: one frame per grid frame, Frame Time 1/24.
  grid_frames=$(awk -v n="$frames" -v ft="$frame_time" 'BEGIN { print int((n - 1) * ft * 24 + 1e-3) + 1 }')
  "$client_bin" skeletal "$clip" -o "$work/$name.24.bvh" --timing "$work/$name.24.csv" \
    --output-rate timing --server "$target" >/dev/null || fail "$name: --output-rate timing failed"
  [ "$(header "$work/$name.24.bvh" Frames)" = "$grid_frames" ] \
    || fail "$name: $(header "$work/$name.24.bvh" Frames) frames at the grid rate, want $grid_frames"
  awk -v a="$(header "$work/$name.24.bvh" "Frame Time")" \
    'BEGIN { exit !(a - 1 / 24 < 1e-12 && 1 / 24 - a < 1e-12) }' \
    || fail "$name: Frame Time $(header "$work/$name.24.bvh" "Frame Time") at the grid rate"
  check_sheet "$work/$name.24.csv" "$(awk 'BEGIN { printf "%.17g", 1 / 24 }')" 3 \
    >"$work/check.txt" || fail "$name at the grid rate: $(cat "$work/check.txt")"
  # Its drawings are the source-rate output's, one per grid frame (at or above 24 fps every
  # grid frame holds a source frame).
  awk -F, 'NR > 1 { print $5 "," $2 "," $3 }' "$work/$name.csv" | sort -u -t, -k1,1n \
    >"$work/per_grid.txt"
  awk -F, 'NR > 1 { print $5 "," $2 "," $3 }' "$work/$name.24.csv" >"$work/at_grid.txt"
  cmp -s "$work/per_grid.txt" "$work/at_grid.txt" \
    || fail "$name: the grid-rate drawings differ from the source-rate ones"
  # The written file reads back.
  "$client_bin" skeletal "$work/$name.24.bvh" -o "$work/again.bvh" --server "$target" \
    >/dev/null || fail "$name: the grid-rate BVH does not read back"
done

# The 120 fps clip, counted in its own frames: no grid column, holds up to 3 x 8.3 ms.
"$client_bin" skeletal "$bvh120" -o "$work/own.bvh" --timing "$work/own.csv" --timing-fps 0 \
  --server "$target" >"$work/own.txt" || fail "--timing-fps 0 failed"
head -1 "$work/own.csv" | grep -qx "output_frame,source_frame,kind,time_s" \
  || fail "--timing-fps 0: $(head -1 "$work/own.csv")"
grep -q "film grid" "$work/own.txt" && fail "--timing-fps 0 printed a film grid line"

# A 24 fps clip: the grid changes nothing, byte for byte.
"$client_bin" skeletal "$bvh24" -o "$work/a.bvh" --timing "$work/a.csv" --server "$target" \
  >/dev/null || fail "24 fps default failed"
"$client_bin" skeletal "$bvh24" -o "$work/b.bvh" --timing "$work/b.csv" --timing-fps 0 \
  --server "$target" >/dev/null || fail "24 fps --timing-fps 0 failed"
cmp -s "$work/a.bvh" "$work/b.bvh" && cmp -s "$work/a.csv" "$work/b.csv" \
  || fail "a 24 fps clip differs with and without the grid"

# A bad --timing-fps: the server's code and message, exit 1, nothing written.
expect_error 1 "INVALID_ARGUMENT: timing_fps: 5000 must be finite and <= 1000" \
  "$client_bin" skeletal "$bvh120" -o "$work/bad.bvh" --timing-fps 5000 --server "$target"
[ ! -e "$work/bad.bvh" ] || fail "a failed call wrote an output file"

stop_server
echo "PASS"

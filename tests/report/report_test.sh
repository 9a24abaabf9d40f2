#!/usr/bin/env bash
# The reports of `koma ... --report` (docs/report.md) on the bundled samples, end to end: the
# real koma_server on a loopback port, the real koma client, Debian's chromium headless.
#   report_test.sh MODE KOMA_SERVER KOMA SAMPLES_DIR PYTHON
# MODE:
#   files    same call -> same report bytes; HTML5 (html5lib strict); self-contained; an
#            unwritable --report fails before the call
#   browser  each sample's report in chromium: figures and counts against the timing and
#            drawing sheets and the printed summary, a screenshot that is not blank
#   player   stepping, scrubbing and playing the pitch's player
#   large    a 100,000-frame clip: report under 20 MB, ready in chromium in under 5 s
# KOMA_REPORT_SHOTS=DIR keeps the screenshots (else they go with the scratch directory).
set -euo pipefail
mode=$1 server_bin=$2 koma=$3 samples=$4 python=$5
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../e2e/lib.sh
source "$here/../e2e/lib.sh"
checks=("$python" "$here/report_checks.py")
shots=${KOMA_REPORT_SHOTS:-$work}
mkdir -p "$shots"

start_server "$server_bin"

# run NAME: the four sample calls, each with its report, sheets and printed summary in $work.
run_samples() {
  local tag=$1
  "$koma" skeletal "$samples/pitch.bvh" -o "$work/pitch.bvh" --timing "$work/pitch.csv" \
    --report "$work/pitch$tag.html" --server "$target" >"$work/pitch.txt" || fail "koma skeletal pitch"
  "$koma" skeletal "$samples/mocap_120fps.bvh" -o "$work/mocap.bvh" --timing "$work/mocap.csv" \
    --report "$work/mocap$tag.html" --server "$target" >"$work/mocap.txt" || fail "koma skeletal mocap"
  "$koma" curves "$samples/arm_head.motion3.json" -o "$work/arm.motion3.json" --timing "$work/arm.csv" \
    --on 3 --tame 1.5 --tsume 1.5 --report "$work/arm$tag.html" --server "$target" >"$work/arm.txt" \
    || fail "koma curves"
  "$koma" lipblink "$samples/talk_blink.motion3.json" -o "$work/talk.motion3.json" \
    --report "$work/talk$tag.html" --server "$target" >"$work/talk.txt" || fail "koma lipblink"
}

case "$mode" in
  files)
    run_samples ""
    run_samples "_again"
    for name in pitch mocap arm talk; do
      cmp "$work/$name.html" "$work/${name}_again.html" || fail "$name: same call, different report bytes"
      grep -qF "report: $work/${name}_again.html" "$work/$name.txt" || fail "$name: summary does not name the report"
    done
    echo "ok: same call, same report bytes (pitch, mocap, arm, talk)"
    "${checks[@]}" validate "$work/pitch.html" "$work/mocap.html" "$work/arm.html" "$work/talk.html" \
      || fail "HTML5 validation"
    # A report that cannot be written is refused before the call, naming the path.
    code=0
    "$koma" skeletal "$samples/pitch.bvh" -o "$work/x.bvh" --report "$work/no/such/dir/r.html" \
      --server "$target" 2>"$work/err.txt" || code=$?
    [ "$code" = 1 ] || fail "unwritable --report: exit $code, want 1"
    grep -qF "$work/no/such/dir/r.html" "$work/err.txt" || fail "unwritable --report: $(cat "$work/err.txt")"
    [ ! -e "$work/x.bvh" ] || fail "unwritable --report: the BVH was written anyway"
    echo "ok: unwritable --report refused before the call: $(cat "$work/err.txt")"
    ;;
  browser)
    run_samples ""
    "${checks[@]}" skeletal "$work/pitch.html" "$work/pitch.csv" "$work/pitch.txt" "$shots/pitch.png" || fail "pitch"
    "${checks[@]}" skeletal "$work/mocap.html" "$work/mocap.csv" "$work/mocap.txt" "$shots/mocap.png" || fail "mocap"
    "${checks[@]}" curves "$work/arm.html" "$work/arm.csv" "$work/arm.txt" "$shots/arm.png" || fail "arm"
    "${checks[@]}" lipblink "$work/talk.html" "$work/talk.txt" "$shots/talk.png" || fail "talk"
    ;;
  player)
    run_samples ""
    "${checks[@]}" player "$work/pitch.html" "$work/pitch.csv" || fail "player"
    ;;
  large)
    "$python" "$here/make_long_bvh.py" "$samples/pitch.bvh" "$work/long.bvh" 100000
    "$koma" skeletal "$work/long.bvh" -o "$work/long_anime.bvh" --timing "$work/long.csv" \
      --report "$work/long.html" --server "$target" --deadline 100 >"$work/long.txt" || fail "koma skeletal long"
    "${checks[@]}" validate "$work/long.html" || fail "long: HTML5"
    "${checks[@]}" large "$work/long.html" "$work/long.csv" 5 20000000 || fail "long"
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
stop_server

#!/usr/bin/env bash
# The reports of `koma ... --report` (docs/report.md) on the bundled samples, end to end: the
# real koma_server on a loopback port, the real koma client, Debian's chromium headless.
#   report_test.sh MODE KOMA_SERVER KOMA SAMPLES_DIR PYTHON WRITE_CAMERA_REPORT
# MODE:
#   files    same call -> same report bytes; HTML5 (html5lib strict); self-contained; an
#            unwritable --report fails before the call
#   browser  each sample's report in chromium (samples/wave.glb too): figures and counts
#            against the timing and drawing sheets and the printed summary, a screenshot that
#            is not blank
#   player   stepping, scrubbing and playing the pitch's player; every bone as long as its
#            BVH OFFSET in the figures drawn
#   variants the browser checks on other options of each command
#   camera   a call with a camera (write_camera_report): one projected view, positions right
#   large    100,000-frame inputs to each RPC: report under 20 MB, ready in chromium in under 5 s
# KOMA_REPORT_SHOTS=DIR keeps the screenshots (else they go with the scratch directory).
set -euo pipefail
mode=$1 server_bin=$2 koma=$3 samples=$4 python=$5 camera_tool=$6
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../e2e/lib.sh
source "$here/../e2e/lib.sh"
checks=("$python" "$here/report_checks.py")
shots=${KOMA_REPORT_SHOTS:-$work}
mkdir -p "$shots"

# Every mode but camera calls the real server.
[ "$mode" = camera ] || start_server "$server_bin"

# run NAME: the four sample calls, each with its report, sheets and printed summary in $work.
run_samples() {
  local tag=$1
  "$koma" skeletal "$samples/pitch.bvh" -o "$work/pitch.bvh" --timing "$work/pitch.csv" \
    --report "$work/pitch$tag.html" --xdts "$work/pitch.xdts" --server "$target" >"$work/pitch.txt" \
    || fail "koma skeletal pitch"
  "$koma" skeletal "$samples/mocap_120fps.bvh" -o "$work/mocap.bvh" --timing "$work/mocap.csv" \
    --report "$work/mocap$tag.html" --xdts "$work/mocap.xdts" --server "$target" >"$work/mocap.txt" \
    || fail "koma skeletal mocap"
  "$koma" curves "$samples/arm_head.motion3.json" -o "$work/arm.motion3.json" --timing "$work/arm.csv" \
    --on 3 --tame 1.5 --tsume 1.5 --report "$work/arm$tag.html" --xdts "$work/arm.xdts" \
    --server "$target" >"$work/arm.txt" \
    || fail "koma curves"
  "$koma" lipblink "$samples/talk_blink.motion3.json" -o "$work/talk_values.csv" \
    --report "$work/talk$tag.html" --xdts "$work/talk.xdts" --server "$target" >"$work/talk.txt" \
    || fail "koma lipblink"
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
    # --report - writes the page to standard output (the summary goes to stderr), the same bytes.
    "$koma" skeletal "$samples/pitch.bvh" -o "$work/y.bvh" --report - --server "$target" \
      >"$work/stdout.html" 2>"$work/stderr.txt" || fail "--report -: $(cat "$work/stderr.txt")"
    cmp "$work/stdout.html" "$work/pitch.html" || fail "--report - differs from the file report"
    grep -qF "report: -" "$work/stderr.txt" || fail "--report -: summary not on stderr"
    code=0
    "$koma" skeletal "$samples/pitch.bvh" -o - --report - --server "$target" >/dev/null \
      2>"$work/err.txt" || code=$?
    [ "$code" = 2 ] || fail "-o - --report -: exit $code, want 2"
    grep -qF -- "--report -" "$work/err.txt" || fail "-o - --report -: $(cat "$work/err.txt")"
    echo "ok: --report - writes standard output; with -o - too it is refused: $(cat "$work/err.txt")"
    ;;
  browser)
    run_samples ""
    "${checks[@]}" skeletal "$work/pitch.html" "$work/pitch.csv" "$work/pitch.txt" "$shots/pitch.png" || fail "pitch"
    "${checks[@]}" skeletal "$work/mocap.html" "$work/mocap.csv" "$work/mocap.txt" "$shots/mocap.png" || fail "mocap"
    "${checks[@]}" curves "$work/arm.html" "$work/arm.csv" "$work/arm.txt" "$shots/arm.png" || fail "arm"
    "${checks[@]}" lipblink "$work/talk.html" "$work/talk.txt" "$shots/talk.png" \
      "$work/talk_values.csv" || fail "talk"
    # A glTF 2.0 file (samples/wave.glb): the report's stick figures are the skin's joints.
    "$koma" skeletal "$samples/wave.glb" -o "$work/wave.glb" --timing "$work/wave.csv" \
      --report "$work/wave.html" --xdts "$work/wave.xdts" --server "$target" >"$work/wave.txt" || fail "koma skeletal wave.glb"
    "${checks[@]}" validate "$work/wave.html" || fail "wave.glb: HTML5 validation"
    "${checks[@]}" skeletal "$work/wave.html" "$work/wave.csv" "$work/wave.txt" "$shots/wave.png" \
      || fail "wave.glb"
    for name in pitch mocap arm talk wave; do
      "${checks[@]}" xdts "$work/$name.html" "$work/$name.xdts" || fail "$name: exposure sheet"
    done
    ;;
  player)
    run_samples ""
    "${checks[@]}" player "$work/pitch.html" "$work/pitch.csv" || fail "player"
    "${checks[@]}" bones "$work/pitch.html" "$samples/pitch.bvh" || fail "pitch bones"
    "${checks[@]}" bones "$work/mocap.html" "$samples/mocap_120fps.bvh" || fail "mocap bones"
    ;;
  variants)
    # Other calls: the TIMING_RATE output, no film grid, no duplicates, holds first, curves
    # on twos with a per-curve override, lipblink's follow mode with auto-blinks.
    "$koma" skeletal "$samples/mocap_120fps.bvh" -o "$work/v1.bvh" --timing "$work/v1.csv" \
      --output-rate timing --report "$work/v1.html" --server "$target" >"$work/v1.txt" || fail "v1"
    "${checks[@]}" skeletal "$work/v1.html" "$work/v1.csv" "$work/v1.txt" || fail "--output-rate timing"
    "$koma" skeletal "$samples/mocap_120fps.bvh" -o "$work/v2.bvh" --timing "$work/v2.csv" \
      --timing-fps 0 --report "$work/v2.html" --server "$target" >"$work/v2.txt" || fail "v2"
    "${checks[@]}" skeletal "$work/v2.html" "$work/v2.csv" "$work/v2.txt" || fail "--timing-fps 0"
    "$koma" skeletal "$samples/pitch.bvh" -o "$work/v3.bvh" --timing "$work/v3.csv" \
      --no-keep-length --hold-first --report "$work/v3.html" --server "$target" >"$work/v3.txt" || fail "v3"
    "${checks[@]}" skeletal "$work/v3.html" "$work/v3.csv" "$work/v3.txt" || fail "--no-keep-length --hold-first"
    "${checks[@]}" player "$work/v3.html" "$work/v3.csv" || fail "--no-keep-length player"
    "$koma" curves "$samples/arm_head.motion3.json" -o "$work/v4.csv" --timing "$work/v4_sheet.csv" \
      --timing-fps 0 --on 2 --curve-on ParamArmLA=3 --report "$work/v4.html" --server "$target" \
      >"$work/v4.txt" || fail "v4"
    "${checks[@]}" curves "$work/v4.html" "$work/v4_sheet.csv" "$work/v4.txt" || fail "curves on twos"
    "$koma" lipblink "$samples/talk_blink.motion3.json" -o "$work/v5.csv" --timing-fps 0 \
      --auto-blink 1 --mode follow --report "$work/v5.html" --server "$target" >"$work/v5.txt" || fail "v5"
    "${checks[@]}" lipblink "$work/v5.html" "$work/v5.txt" "" "$work/v5.csv" || fail "lipblink follow, auto-blink"
    # Through a camera (one projected view per side), and with no motion in the answer.
    "$koma" skeletal "$samples/pitch.bvh" -o "$work/v6.bvh" --timing "$work/v6.csv" \
      --camera 0.01,0,0,0,0,0.01,0,0,0,0,0.01,0,0,0,0,1 --report "$work/v6.html" --server "$target" \
      >"$work/v6.txt" || fail "v6"
    "${checks[@]}" skeletal "$work/v6.html" "$work/v6.csv" "$work/v6.txt" || fail "--camera"
    "$koma" skeletal "$samples/mocap_120fps.bvh" --timing-only --timing "$work/v7.csv" \
      --report "$work/v7.html" --server "$target" >"$work/v7.txt" || fail "v7"
    "${checks[@]}" skeletal "$work/v7.html" "$work/v7.csv" "$work/v7.txt" || fail "--timing-only"
    # LipBlink with only a mouth, and with only eyes (200 frames of make_long_curves' talk).
    "$python" "$here/make_long_curves.py" 200 "$work/talk200.csv" "$work/curves200.csv"
    cut -d, -f1,2 "$work/talk200.csv" >"$work/mouth_only.csv"
    cut -d, -f1,3,4 "$work/talk200.csv" >"$work/eyes_only.csv"
    for part in mouth_only eyes_only; do
      "$koma" lipblink "$work/$part.csv" -o "$work/${part}_out.csv" --report "$work/$part.html" \
        --server "$target" >"$work/$part.txt" || fail "koma lipblink $part"
      "${checks[@]}" lipblink "$work/$part.html" "$work/$part.txt" "" "$work/${part}_out.csv" \
        || fail "lipblink $part"
    done
    # Cuts (issue 28) on clips made from a real BVH: a T-pose first frame (one cut) and a glitch
    # frame (two cuts), marked on the speed plot at the summary's source frames.
    "$python" "$here/../e2e/make_real_takes.py" "$here/../testdata/bvh_test1.bvh" "$work"
    for clip in tpose glitch; do
      "$koma" skeletal "$work/$clip.bvh" -o "$work/${clip}_out.bvh" --timing "$work/$clip.csv" \
        --report "$work/$clip.html" --server "$target" >"$work/$clip.txt" || fail "koma skeletal $clip"
      grep -q "cuts " "$work/$clip.txt" || fail "$clip: the summary names no cut"
      "${checks[@]}" skeletal "$work/$clip.html" "$work/$clip.csv" "$work/$clip.txt" || fail "$clip: cut marks"
    done
    "${checks[@]}" validate "$work"/v[1-7].html "$work/mouth_only.html" "$work/eyes_only.html" \
      "$work/tpose.html" "$work/glitch.html" || fail "variants: HTML5"
    ;;
  large)
    "$python" "$here/make_long_bvh.py" "$samples/pitch.bvh" "$work/long.bvh" 100000
    "$koma" skeletal "$work/long.bvh" -o "$work/long_anime.bvh" --timing "$work/long.csv" \
      --report "$work/long.html" --server "$target" --deadline 100 >"$work/long.txt" || fail "koma skeletal long"
    "${checks[@]}" validate "$work/long.html" || fail "long: HTML5"
    "${checks[@]}" large "$work/long.html" "$work/long.csv" 5 20000000 || fail "long"
    # The same for 100,000 frames of curves (30 fps, 55 minutes) through the other two RPCs.
    "$python" "$here/make_long_curves.py" 100000 "$work/long_talk.csv" "$work/long_curves.csv"
    "$koma" lipblink "$work/long_talk.csv" -o "$work/long_talk_out.csv" --report "$work/long_talk.html" \
      --server "$target" --deadline 100 >"$work/long_talk.txt" || fail "koma lipblink long"
    "${checks[@]}" opens "$work/long_talk.html" 5 20000000 || fail "long lipblink"
    "$koma" curves "$work/long_curves.csv" -o "$work/long_curves_out.csv" --keys 0,50000,99999 \
      --report "$work/long_curves.html" --server "$target" --deadline 100 >"$work/long_curves.txt" \
      || fail "koma curves long"
    "${checks[@]}" opens "$work/long_curves.html" 5 20000000 || fail "long curves"
    ;;
  voice)
    # A recording (made by samples/make_voice.sh with espeak-ng and sox) and a new motion.
    for tag in "" _again; do
      "$koma" lipblink --audio "$samples/voice.flac" -o "$work/voice.csv" --auto-blink 3 \
        --report "$work/voice$tag.html" --xdts "$work/voice$tag.xdts" --server "$target" \
        >"$work/voice$tag.txt" || fail "koma lipblink --audio"
    done
    cmp "$work/voice.html" "$work/voice_again.html" || fail "voice: same call, different report bytes"
    grep -qF "report: $work/voice.html" "$work/voice.txt" || fail "voice: summary does not name the report"
    "${checks[@]}" validate "$work/voice.html" || fail "voice: HTML5"
    "${checks[@]}" voice "$work/voice.html" "$work/voice.txt" "$shots/voice.png" || fail "voice"
    "${checks[@]}" lipblink "$work/voice.html" "$work/voice.txt" "" "$work/voice.csv" || fail "voice: drawings and face"
    "${checks[@]}" xdts "$work/voice.html" "$work/voice.xdts" || fail "voice: exposure sheet"
    # Over --report-audio-max-bytes the page links the recording by its relative path.
    mkdir -p "$work/sub/pages" "$work/sub/sound"
    cp "$samples/voice.flac" "$work/sub/sound/take 1.flac"
    "$koma" lipblink --audio "$work/sub/sound/take 1.flac" -o "$work/linked.motion3.json" --mode follow \
      --report "$work/sub/pages/linked.html" --report-audio-max-bytes 1000 --server "$target" \
      >"$work/linked.txt" || fail "koma lipblink --report-audio-max-bytes"
    grep -qF '"src":"../sound/take%201.flac"' "$work/sub/pages/linked.html" || fail "linked: no relative link"
    "${checks[@]}" voice "$work/sub/pages/linked.html" "$work/linked.txt" || fail "voice, linked"
    # The page plays the other formats koma reads: WAV (16-bit, float), Ogg Vorbis, MP3.
    for f in voice16.wav voice_float.wav voice.ogg voice.mp3; do
      case $f in *float*) enc=(-e floating-point -b 32) ;; *16*) enc=(-b 16) ;; *) enc=() ;; esac
      sox "$samples/voice.flac" "${enc[@]}" "$work/$f" || fail "sox $f"
      "$koma" lipblink --audio "$work/$f" -o "$work/$f.motion3.json" --report "$work/$f.html" \
        --server "$target" >"$work/$f.txt" || fail "koma lipblink --audio $f"
      "${checks[@]}" audio "$work/$f.html" "$work/$f.txt" || fail "voice: $f"
    done
    # Rhubarb cues in: no recording, the drawings and the face on the page's clock.
    "$koma" lipblink --audio "$samples/voice.flac" -o "$work/c.motion3.json" --cues "$work/cues.tsv" \
      --server "$target" >/dev/null || fail "koma lipblink --cues"
    "$koma" lipblink --rhubarb "$work/cues.tsv" -o "$work/rhubarb.csv" --report "$work/rhubarb.html" \
      --xdts "$work/rhubarb.xdts" --server "$target" >"$work/rhubarb.txt" \
      || fail "koma lipblink --rhubarb --report"
    "${checks[@]}" validate "$work/rhubarb.html" || fail "rhubarb: HTML5"
    "${checks[@]}" lipblink "$work/rhubarb.html" "$work/rhubarb.txt" "$shots/rhubarb.png" "$work/rhubarb.csv" \
      || fail "rhubarb: drawings and face"
    "${checks[@]}" xdts "$work/rhubarb.html" "$work/rhubarb.xdts" || fail "rhubarb: exposure sheet"
    ;;
  camera)
    "$camera_tool" "$work/camera.html" || fail "write_camera_report"
    "${checks[@]}" validate "$work/camera.html" || fail "camera: HTML5"
    "${checks[@]}" camera "$work/camera.html" || fail "camera"
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
[ -z "$server_pid" ] || stop_server

#!/usr/bin/env bash
# The main job on the bundled samples: install the build dependencies only, build the two
# programs only (koma_server and koma: scripts/build.sh --programs; test.sh builds the rest),
# start koma_server on a loopback port,
# retime samples/pitch.bvh (RetimeSkeletal), samples/arm_head.motion3.json (RetimeCurves) and
# samples/talk_blink.motion3.json (LipBlink) through the koma client, write the results and
# their timing sheets to out/, print the summaries and the paths of their HTML reports, stop
# the server. KOMA_OUT_DIR names another folder than ./out (the docs test uses a scratch one).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_BUILD_DIR:-$root/build}
out=${KOMA_OUT_DIR:-$root/out}
mkdir -p "$out"
KOMA_BUILD_LOG="$out/build.log" "$root/scripts/build.sh" --programs

port_file=$(mktemp)
"$build/server/koma_server" --address=127.0.0.1:0 --port_file="$port_file" \
  2>"$out/server.log" &
server_pid=$!
trap 'kill -TERM $server_pid 2>/dev/null || true; rm -f "$port_file"' EXIT
for _ in $(seq 100); do [ -s "$port_file" ] && break; sleep 0.1; done
[ -s "$port_file" ] || { echo "koma_server did not start; see $out/server.log" >&2; exit 1; }
server=127.0.0.1:$(cat "$port_file")

echo "koma_server is $("$build/client/koma" health --server "$server") on $server"
"$build/client/koma" skeletal "$root/samples/pitch.bvh" -o "$out/pitch_anime.bvh" \
  --timing "$out/pitch_timing.csv" --report "$out/pitch_report.html" --server "$server"
echo
echo "First output frames of the timing sheet ($out/pitch_timing.csv):"
head -n 13 "$out/pitch_timing.csv"
echo
# Real 120 fps mocap (pybvh's test fixture, MIT): drawings counted on the 24 fps film grid, so
# holds last 1/12 or 1/8 s as on a film, not 3 frames of 120 fps (25 ms).
"$build/client/koma" skeletal "$root/samples/mocap_120fps.bvh" -o "$out/mocap_120fps_anime.bvh" \
  --timing "$out/mocap_120fps_timing.csv" --report "$out/mocap_120fps_report.html" --server "$server"
echo
"$build/client/koma" curves "$root/samples/arm_head.motion3.json" \
  -o "$out/arm_head_anime.motion3.json" --timing "$out/arm_head_drawings.csv" --on 3 \
  --tame 1.5 --tsume 1.5 --report "$out/arm_head_report.html" --server "$server"
echo
"$build/client/koma" lipblink "$root/samples/talk_blink.motion3.json" \
  -o "$out/talk_blink_anime.motion3.json" --report "$out/talk_blink_report.html" --server "$server"

kill -TERM "$server_pid"
wait "$server_pid"
trap - EXIT
rm -f "$port_file"
echo "koma_server stopped cleanly; its log is $out/server.log"
echo
echo "Before/after reports (self-contained HTML, open in any browser; docs/report.md):"
for report in pitch_report mocap_120fps_report arm_head_report talk_blink_report; do
  echo "  $out/$report.html"
done

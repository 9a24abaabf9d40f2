#!/usr/bin/env bash
# The main job on the bundled sample: install, build, start koma_server on a loopback port,
# retime samples/pitch.bvh through the koma client, write out/pitch_anime.bvh and
# out/pitch_timing.csv, print the summary, stop the server.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${KOMA_BUILD_DIR:-$root/build}
out=$root/out
mkdir -p "$out"
KOMA_BUILD_LOG="$out/build.log" "$root/scripts/build.sh"

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
  --timing "$out/pitch_timing.csv" --server "$server"
echo
echo "First output frames of the timing sheet ($out/pitch_timing.csv):"
head -n 13 "$out/pitch_timing.csv"

kill -TERM "$server_pid"
wait "$server_pid"
trap - EXIT
rm -f "$port_file"
echo "koma_server stopped cleanly; its log is $out/server.log"

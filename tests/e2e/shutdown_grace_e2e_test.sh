#!/usr/bin/env bash
# End to end (issue 42): SIGTERM during a call that computes for seconds stops the real
# koma_server within --shutdown_grace_ms (plus its 0.2 s margin and the test's own slack), with
# exit code 0 and the reason in its log; a drain with nothing in flight still ends at once.
# Two slow calls: a GLB of 60,000 one-channel animations (made here; --max_gltf_animations
# raised to let it in), whose tinygltf parse cannot be interrupted, so the server's watchdog
# usually exits without it (or, if the call has reached its polled loops, it stops itself); and a FLAC of unknown length (1.3 G samples of silence, made by
# hostile/hostile_files.py), whose decoding polls the call's stop signal, so gRPC's
# cancellation at the end of the grace stops it and the call is logged CANCELLED.
# Usage: shutdown_grace_e2e_test.sh KOMA_SERVER KOMA [PYTHON]
set -euo pipefail
server_bin=$1 client_bin=$2 python=${3:-/usr/bin/python3}

source "$(dirname "$0")/lib.sh"

python3 - "$work/many.glb" <<'PY'
import json, struct, sys
n = 60000
data = struct.pack('<2f', 0.0, 1.0) + struct.pack('<6f', 0, 0, 0, 1, 2, 3)
doc = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
       "nodes": [{"name": "root", "children": [1]}, {"name": "arm", "translation": [0, 1, 0]}],
       "buffers": [{"byteLength": len(data)}],
       "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 8},
                       {"buffer": 0, "byteOffset": 8, "byteLength": 24}],
       "accessors": [{"bufferView": 0, "componentType": 5126, "count": 2, "type": "SCALAR",
                      "min": [0], "max": [1]},
                     {"bufferView": 1, "componentType": 5126, "count": 2, "type": "VEC3"}],
       "animations": [{"name": f"a{i}",
                       "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
                       "samplers": [{"input": 0, "output": 1}]} for i in range(n)]}
text = json.dumps(doc, separators=(',', ':')).encode()
text += b' ' * (-len(text) % 4)
glb = (b'glTF' + struct.pack('<II', 2, 12 + 8 + len(text) + 8 + len(data)) +
       struct.pack('<I', len(text)) + b'JSON' + text + struct.pack('<I', len(data)) + b'BIN\0' + data)
open(sys.argv[1], 'wb').write(glb)
PY

grace_ms=500
# sigterm_during WHAT SERVER_FLAGS... -- CLIENT_ARGS...: starts the server with the flags, the
# client call in the background, sends SIGTERM 1.5 s in (the call still running), and checks
# the server stopped within the grace plus 1.5 s and the call did not succeed.
sigterm_during() {
  local what=$1 flags=() client_pid
  shift
  while [ "$1" != "--" ]; do flags+=("$1"); shift; done
  shift
  : >"$work/server.log"
  start_server "$server_bin" --shutdown_delay_ms=0 --shutdown_grace_ms=$grace_ms \
    --worker_threads=1 "${flags[@]}"
  "$client_bin" "$@" --server "$target" --deadline 60 -q >"$work/client.out" 2>&1 &
  client_pid=$!
  sleep 1.5
  not_running "$client_pid" && fail "$what ended within 1.5 s: $(cat "$work/client.out")"
  stop_server 10
  # shellcheck disable=SC2154  # set by stop_server_as (lib.sh)
  echo "$what: stopped ${stopped_ms} ms after SIGTERM (grace ${grace_ms} ms)"
  [ "$stopped_ms" -lt $((grace_ms + 1500)) ] ||
    fail "the server took ${stopped_ms} ms to stop, grace ${grace_ms} ms"
  wait "$client_pid" && fail "the cancelled call ($what) succeeded"
  return 0
}

sigterm_during "the GLB" --max_gltf_animations=100000 -- \
  skeletal "$work/many.glb" -o "$work/many_anime.glb"
# Usually still inside tinygltf's parse at the end of the grace, so the watchdog exits; on a
# loaded machine the call may have reached its polled loops and stop by itself: either way the
# log says why.
grep -q 'exiting without them\|"code":"CANCELLED".*the work stopped\|code=CANCELLED.*the work stopped' \
  "$work/server.log" || fail "the log does not say why it exited: $(tail -3 "$work/server.log")"

# A call that polls its stop signal: cancelled at the end of the grace, logged, no watchdog.
PYTHONPATH="$(dirname "$0")/hostile" "$python" -c '
import sys, hostile_files
open(sys.argv[1], "wb").write(hostile_files.flac_silence(1_000_000, 8, 2500, 0))' "$work/long.flac"
sigterm_during "the decoding" --max_audio_samples=100000000000 --log_format=json -- \
  lipblink --audio "$work/long.flac" -o "$work/voice.motion3.json"
grep -q '"code":"CANCELLED".*the work stopped' "$work/server.log" ||
  fail "the decoding call is not logged CANCELLED: $(tail -3 "$work/server.log")"
grep -q "exiting without them" "$work/server.log" &&
  fail "the watchdog exited although the call polls its stop signal"

# Nothing in flight: the drain ends at once, without the forced exit.
start_server "$server_bin" --shutdown_delay_ms=0 --shutdown_grace_ms=5000
"$client_bin" health --server "$target" >/dev/null || fail "health failed"
: >"$work/server.log"
stop_server 10
[ "$stopped_ms" -lt 2000 ] || fail "an idle server took ${stopped_ms} ms to stop"
grep -q "exiting without them" "$work/server.log" && fail "an idle drain was forced"
echo "shutdown grace: ok"

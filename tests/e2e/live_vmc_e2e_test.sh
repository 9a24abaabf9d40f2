#!/usr/bin/env bash
# `koma live --vmc` against the real koma_server and a real OSC receiver (python3-liblo on a
# loopback UDP port, and Debian's oscdump): one bundle per grid frame whose blend shape values
# are the same run's --json frames (tests/e2e/vmc_receiver.py), VRM 1.0 clip names and other
# mouth levels, and a receiver that is not there (the stream goes on, one warning).
# Usage: live_vmc_e2e_test.sh KOMA_SERVER KOMA PYTHON VOICE_FLAC
set -euo pipefail
# liblo's receivers (python3-liblo, oscdump) bind the wildcard address, not 127.0.0.1: where
# unshare can make one, the test runs in a network namespace of its own whose only interface is
# loopback, so nothing outside reaches them.
if [ -z "${KOMA_LIVE_NETNS:-}" ] && unshare -rn true 2>/dev/null; then
  exec env KOMA_LIVE_NETNS=1 unshare -rn bash -c 'ip link set lo up && exec "$0" "$@"' "$0" "$@"
fi
server_bin=$1 koma=$2 python=$3 voice=$4
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
source "$here/lib.sh"
receiver="$here/vmc_receiver.py"

start_server "$server_bin"

# receive_during NAME KOMA_ARGS...: koma live --input VOICE --speed 0 --json with KOMA_ARGS
# and --vmc to a fresh receiver; its bundles in $work/NAME.bundles.json, frames in NAME.jsonl.
receive_during() {
  local name=$1
  shift
  "$python" "$receiver" receive "$work/$name.port" "$work/$name.bundles.json" \
    "$work/$name.stop" 2>>"$work/receiver.log" &
  local pid=$!
  pids_to_kill+=("$pid")
  wait_until 10 test -s "$work/$name.port" || fail "$name: the receiver did not start"
  "$koma" live --server "$target" --input "$voice" --speed 0 --json \
    --vmc "127.0.0.1:$(cat "$work/$name.port")" "$@" >"$work/$name.jsonl" 2>"$work/$name.err" ||
    fail "$name: koma live exited $?: $(cat "$work/$name.err")"
  touch "$work/$name.stop"
  reap "$pid" || fail "$name: the receiver failed"
}

# 1. VRM 0.x defaults ("A", "Blink"), the mouth's default levels 0 / 0.5 / 1, auto-blinks so
#    the blink clip moves too.
receive_during vrm0 --auto-blink 0.5
"$python" "$receiver" check "$work/vrm0.bundles.json" "$work/vrm0.jsonl" A Blink 0 1 ||
  fail "vrm0: the bundles are not the frames"
grep -q '"mouth":"open"' "$work/vrm0.jsonl" || fail "vrm0: the voice never opened the mouth"
grep -q '"blink":true' "$work/vrm0.jsonl" || fail "vrm0: no blink in the run"
if [ -s "$work/vrm0.err" ] && grep -q 'warning: --vmc' "$work/vrm0.err"; then
  fail "vrm0: a warning with a receiver listening: $(cat "$work/vrm0.err")"
fi

# 2. VRM 1.0 names and mouth levels 2..6: the values are still 0 / 0.5 / 1 (normalised).
receive_during vrm1 --vmc-mouth-clip aa --vmc-blink-clip blink --mouth-min 2 --mouth-max 6
"$python" "$receiver" check "$work/vrm1.bundles.json" "$work/vrm1.jsonl" aa blink 2 6 ||
  fail "vrm1: the bundles are not the frames"

# 3. Debian's oscdump as the receiver: three messages per frame, Apply last.
port=$(free_port)
oscdump -L "$port" >"$work/oscdump.txt" 2>>"$work/receiver.log" &
dump_pid=$!
pids_to_kill+=("$dump_pid")
sleep 0.5  # oscdump prints nothing when it is ready; its bind takes milliseconds
"$koma" live --server "$target" --input "$voice" --speed 0 --json --vmc "127.0.0.1:$port" \
  >"$work/dump.jsonl" 2>"$work/dump.err" || fail "oscdump run: koma live failed"
dump_complete() {
  [ "$(grep -c '/VMC/Ext/Blend/Apply' "$work/oscdump.txt")" -ge "$(wc -l <"$work/dump.jsonl")" ]
}
wait_until 10 dump_complete || true  # counted below
kill "$dump_pid"
reap "$dump_pid" || true
frames=$(wc -l <"$work/dump.jsonl")
applies=$(grep -c '^[0-9a-f.]* /VMC/Ext/Blend/Apply *$' "$work/oscdump.txt" || true)
mouths=$(grep -c '^[0-9a-f.]* /VMC/Ext/Blend/Val sf "A" [0-9.]*$' "$work/oscdump.txt" || true)
blinks=$(grep -c '^[0-9a-f.]* /VMC/Ext/Blend/Val sf "Blink" [0-9.]*$' "$work/oscdump.txt" || true)
[ "$frames" -gt 0 ] && [ "$applies" = "$frames" ] && [ "$mouths" = "$frames" ] &&
  [ "$blinks" = "$frames" ] ||
  fail "oscdump: $applies Apply, $mouths A, $blinks Blink for $frames frames"

# 4. Nobody listening: UDP loses the frames, the stream and its exit code do not change.
port=$(free_port)
"$koma" live --server "$target" --input "$voice" --speed 0 --json --vmc "127.0.0.1:$port" \
  >"$work/none.jsonl" 2>"$work/none.err" || fail "no receiver: koma live failed"
[ "$(wc -l <"$work/none.jsonl")" = "$frames" ] || fail "no receiver: frames missing"
[ "$(grep -c 'cannot send' "$work/none.err" || true)" -le 1 ] ||
  fail "no receiver: more than one warning: $(cat "$work/none.err")"

# 5. Usage errors exit 2 naming the flag.
expect_exit 2 "$work/usage.err" "$koma" live --input "$voice" --vmc 127.0.0.1:0
grep -q -- '--vmc' "$work/usage.err" || fail "bad --vmc port: $(cat "$work/usage.err")"
expect_exit 2 "$work/usage.err" "$koma" live --input "$voice" --vmc-blink-clip ""
grep -q -- '--vmc-blink-clip' "$work/usage.err" || fail "empty clip: $(cat "$work/usage.err")"

stop_server
echo "PASS live_vmc: $frames frames, one bundle each (python3-liblo, oscdump)"

#!/usr/bin/env bash
# `koma live --vts` against the real koma_server and a stand-in for VTube Studio's plugin API
# (tests/e2e/vts_standin.py: python3-websockets on loopback, answering as the API README
# documents and checking every request's shape; there is no VTube Studio on Linux). The flows:
# a new token asked for and saved, the saved token reused, a refused token replaced, the user
# clicking Deny, nothing listening; every frame injected with the same run's --json values; the
# values re-sent at least once a second while frames are slower; an unknown parameter's
# APIError printed once.
# Usage: live_vts_e2e_test.sh KOMA_SERVER KOMA PYTHON VOICE_FLAC
set -euo pipefail
server_bin=$1 koma=$2 python=$3 voice=$4
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=lib.sh
source "$here/lib.sh"
standin="$here/vts_standin.py"

start_server "$server_bin"

# start_standin NAME [FLAGS...]: a stand-in logging to $work/NAME.log; sets $vts_url, $standin_pid.
start_standin() {
  local name=$1
  shift
  "$python" "$standin" serve "$work/$name.port" "$work/$name.log" "$@" \
    2>>"$work/standin.log" &
  standin_pid=$!
  pids_to_kill+=("$standin_pid")
  wait_until 10 test -s "$work/$name.port" || fail "$name: the stand-in did not start"
  vts_url="ws://127.0.0.1:$(cat "$work/$name.port")"
}
stop_standin() {
  kill -TERM "$standin_pid"
  reap "$standin_pid" || fail "the stand-in exited with an error: $(cat "$work/standin.log")"
}
# live NAME KOMA_ARGS...: koma live on the voice with --json and --vts $vts_url; frames in
# $work/NAME.jsonl, stderr in $work/NAME.err; fails unless it exits 0.
live() {
  local name=$1
  shift
  "$koma" live --server "$target" --input "$voice" --json --vts "$vts_url" "$@" \
    >"$work/$name.jsonl" 2>"$work/$name.err" ||
    fail "$name: koma live exited $?: $(cat "$work/$name.err")"
}
check() {
  local name=$1
  shift
  "$python" "$standin" check "$work/$name.log" "$work/$name.jsonl" "$@" ||
    fail "$name: the requests do not match the frames"
}

# 1. No token yet: AuthenticationTokenRequest, the token saved at the default place
#    ($XDG_CONFIG_HOME/koma/vts-token, folders created, 0600), AuthenticationRequest, then one
#    inject per frame (auto-blinks so the eyes move too).
export XDG_CONFIG_HOME="$work/xdg"
start_standin new --token token-one
live new --speed 0 --auto-blink 0.5
stop_standin
check new --flow new
token_file="$XDG_CONFIG_HOME/koma/vts-token"
[ "$(cat "$token_file")" = token-one ] || fail "new: the token was not saved in $token_file"
[ "$(stat -c %a "$token_file")" = 600 ] || fail "new: $token_file is not 0600"
grep -q '"blink":true' "$work/new.jsonl" || fail "new: no blink in the run"
grep -q 'click "Allow"' "$work/new.err" || fail "new: the user was not told to click Allow"

# 2. The saved token: AuthenticationRequest alone; other parameter names and mouth levels.
start_standin saved --valid-token token-one
live saved --speed 0 --mouth-min 2 --mouth-max 6 --vts-mouth-param MouthSmile \
  --vts-eye-left-param EyeLeftX --vts-eye-right-param EyeRightX
stop_standin
check saved --flow saved --mouth MouthSmile --left EyeLeftX --right EyeRightX \
  --mouth-min 2 --mouth-max 6
! grep -q 'Allow' "$work/saved.err" || fail "saved: asked for a new token"

# 3. The saved token refused (revoked): a new one asked for, saved over the old, used.
start_standin refreshed --token token-two
live refreshed --speed 0 --vts-token-file "$token_file"
stop_standin
check refreshed --flow refreshed
[ "$(cat "$token_file")" = token-two ] || fail "refreshed: the new token was not saved"

# 4. Frames 1.04 s apart (0.25 s of audio at 0.04x): the last values are re-sent, so VTube
#    Studio never goes a second without them.
start_standin slow --valid-token token-two
live slow --speed 0.04 --seconds 0.25
stop_standin
check slow --flow saved --max-gap 0.75

# 5. A parameter VTube Studio does not have: APIError 453 printed once, the stream goes on.
start_standin unknown --valid-token token-two
live unknown --speed 0 --vts-mouth-param KomaNoSuchParameter
stop_standin
[ "$(grep -c 'APIError 453' "$work/unknown.err")" = 1 ] ||
  fail "unknown parameter: want one APIError 453 line: $(cat "$work/unknown.err")"

# 6. The user clicks Deny: exit 1 before any audio, errorID 50 and what to do; no token saved.
start_standin denied --deny
expect_exit 1 "$work/denied.err" "$koma" live --server "$target" --input "$voice" --speed 0 \
  --vts "$vts_url" --vts-token-file "$work/denied/vts-token"
stop_standin
grep -q 'APIError 50' "$work/denied.err" && grep -q 'click Allow' "$work/denied.err" ||
  fail "denied: $(cat "$work/denied.err")"
[ ! -e "$work/denied/vts-token" ] || fail "denied: a token file was written"
! grep -q InjectParameterDataRequest "$work/denied.log" || fail "denied: injects were sent"

# 7. Mid-stream: access revoked (APIError 8 from the 11th frame), or VTube Studio quitting
#    (the connection closed after 10 frames), ends the stream with exit 1 and the reason;
#    no inject is sent after the one that found out.
for how in revoke close; do
  start_standin "$how" --valid-token token-two "--$how-after" 10
  expect_exit 1 "$work/$how.err" "$koma" live --server "$target" --input "$voice" \
    --seconds 2 --json --vts "$vts_url" --vts-token-file "$token_file" >"$work/$how.jsonl"
  stop_standin
  [ "$(wc -l <"$work/$how.jsonl")" -lt 48 ] || fail "$how: the stream did not end early"
  injects=$(grep -c InjectParameterDataRequest "$work/$how.log" || true)
  [ "$injects" -le 13 ] || fail "$how: $injects injects sent, want at most 13"
done
grep -q 'APIError 8' "$work/revoke.err" || fail "revoked: $(cat "$work/revoke.err")"
grep -q 'closed the connection' "$work/close.err" || fail "closed: $(cat "$work/close.err")"

# 8. Nothing listening: exit 1 naming the URL and the setting to check.
port=$(free_port)
expect_exit 1 "$work/closed.err" "$koma" live --server "$target" --input "$voice" --speed 0 \
  --vts "ws://127.0.0.1:$port"
grep -q "ws://127.0.0.1:$port" "$work/closed.err" && grep -q 'allow plugins' "$work/closed.err" ||
  fail "nothing listening: $(cat "$work/closed.err")"

# 9. Usage errors exit 2 naming the flag.
expect_exit 2 "$work/usage.err" "$koma" live --input "$voice" --vts wss://127.0.0.1:8001
grep -q -- '--vts' "$work/usage.err" || fail "wss: $(cat "$work/usage.err")"
expect_exit 2 "$work/usage.err" "$koma" live --input "$voice" --vts-mouth-param ""
grep -q -- '--vts-mouth-param' "$work/usage.err" || fail "empty param: $(cat "$work/usage.err")"

stop_server
echo "PASS live_vts: new, saved and refreshed tokens, Deny, keep-alive, APIErrors, revoked, closed"

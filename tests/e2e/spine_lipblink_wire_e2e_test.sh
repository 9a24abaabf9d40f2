#!/usr/bin/env bash
# End to end: LipBlink into a Spine skeleton over the wire (LipBlinkRequest.spine_json), the
# real koma_server on a free loopback port. `koma lipblink SKELETON --animation ...` sends the
# skeleton and writes the server's; --send-file (what it always does) gives the same bytes;
# --report writes the LipBlink report (the voice report with a recording) of the slots;
# `koma batch lipblink` over named skeletons and an @list writes, per skeleton, the bytes the
# single-file command writes; a skeleton batch refuses bad slots per file, naming it.
# Usage: spine_lipblink_wire_e2e_test.sh KOMA_SERVER KOMA SAMPLES_DIR SPINE_TESTDATA_DIR
set -euo pipefail
server_bin=$1 client_bin=$2 samples=$3 data=$4
here=$(dirname "$0")

source "$here/lib.sh"

start_server "$server_bin"

flags=(--animation walk --speech 3-20 --mouth-slot mouth --eye-slot eyes --auto-blink 1.5
       --server "$target")
"$client_bin" lipblink "$data/hero-4.1.json" "${flags[@]}" -o "$work/walk.json" \
  --report "$work/walk.report.html" >"$work/walk.txt" || fail "koma lipblink --report failed"
grep -q 'animation "walk", slot mouth [0-9]* keys, slot eyes [0-9]* keys' "$work/walk.txt" ||
  fail "summary: $(cat "$work/walk.txt")"
grep -q 'walk.report.html' "$work/walk.txt" || fail "no report line: $(cat "$work/walk.txt")"
[ -s "$work/walk.report.html" ] || fail "no report written"
# The report's figures are of the slots (the curves the server converted).
grep -q '"mouth"' "$work/walk.report.html" || fail "the report lacks the mouth slot"
grep -q '"eyes"' "$work/walk.report.html" || fail "the report lacks the eye slot"
grep -q '"mouth_open"\|eyes_closed' "$work/walk.json" || fail "walk.json has no keys"

# --send-file: the same request, the same bytes.
"$client_bin" lipblink "$data/hero-4.1.json" "${flags[@]}" --send-file -o "$work/walk2.json" \
  >/dev/null || fail "koma lipblink --send-file failed"
cmp -s "$work/walk.json" "$work/walk2.json" || fail "--send-file wrote other bytes"

# With a recording: the voice report.
"$client_bin" lipblink "$samples/hero.json" --animation talk --audio "$samples/voice.flac" \
  --mouth-slot mouth --eye-slot eyes --server "$target" -o "$work/talk.json" \
  --report "$work/talk.report.html" >/dev/null || fail "koma lipblink --audio --report failed"
[ -s "$work/talk.report.html" ] || fail "no voice report written"
grep -q 'voice.flac' "$work/talk.report.html" || fail "the voice report does not name the recording"

# Batch: two named skeletons and one from an @list, against single-file runs.
mkdir -p "$work/in"
cp "$data/hero-4.1.json" "$data/hero-4.2.json" "$data/hero-3.8.json" "$work/in/"
echo "$work/in/hero-3.8.json" >"$work/list.txt"
"$client_bin" batch lipblink "$work/in/hero-4.1.json" "$work/in/hero-4.2.json" @"$work/list.txt" \
  "${flags[@]}" -o "$work/out" --report >"$work/batch.txt" 2>&1 ||
  fail "koma batch lipblink failed: $(cat "$work/batch.txt")"
for name in hero-4.1 hero-4.2 hero-3.8; do
  # hero-4.2 has no eye keys in walk and hero-3.8 walk none either: auto-blink and speech.
  "$client_bin" lipblink "$work/in/$name.json" "${flags[@]}" -o "$work/$name.single.json" \
    >/dev/null || fail "single $name failed"
  out=$(find "$work/out" -name "$name.json" | head -n 1)
  [ -n "$out" ] || fail "batch wrote no $name.json: $(find "$work/out")"
  cmp -s "$out" "$work/$name.single.json" || fail "batch $name differs from the single run"
  [ -n "$(find "$work/out" -name "$name*.report.html")" ] || fail "batch wrote no $name report: $(ls "$work/out")"
done

# A bad slot: that file fails, naming itself and the flag; the batch exits 1.
mkdir -p "$work/bad"
expect_exit 1 "$work/bad.err" "$client_bin" batch lipblink "$data/hero-4.1.json" --animation walk \
  --mouth-slot nose --speech 3-9 -o "$work/bad" --server "$target" --summary "$work/bad.json"
grep -q 'hero-4.1.json: --mouth-slot no slot named' "$work/bad.err" "$work/bad.json" ||
  fail "batch: $(cat "$work/bad.err" "$work/bad.json")"
# Without the Spine flags a skeleton is still refused, pointing at them.
expect_exit 1 "$work/bad2.err" "$client_bin" batch lipblink "$data/hero-4.1.json" -o "$work/bad2" \
  --server "$target" --summary "$work/bad2.json"
grep -q 'is a Spine skeleton' "$work/bad2.err" "$work/bad2.json" ||
  fail "batch: $(cat "$work/bad2.err" "$work/bad2.json")"

stop_server
echo "spine lipblink wire e2e: ok"

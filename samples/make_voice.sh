#!/usr/bin/env bash
# Writes samples/voice.flac: two sentences spoken by espeak-ng (English, then Japanese), joined
# by sox with 0.4 s of silence before, 0.8 s between and 0.5 s after, at 16 kHz mono 16-bit.
# Debian's espeak-ng and sox (scripts/install-deps.sh); nothing is downloaded.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
espeak-ng -v en-us+m3 -w "$work/en.wav" "hello from koma"
espeak-ng -v ja+f3 -w "$work/ja.wav" "きょうはいいてんきですね"
for part in en ja; do  # each sentence trimmed to its sound, resampled to 16 kHz
  sox "$work/$part.wav" -r 16000 "$work/$part.16k.wav" silence 1 0.01 1% reverse silence 1 0.01 1% reverse
done
sox -n -r 16000 -c 1 -b 16 "$work/s04.wav" trim 0 0.4
sox -n -r 16000 -c 1 -b 16 "$work/s08.wav" trim 0 0.8
sox -n -r 16000 -c 1 -b 16 "$work/s05.wav" trim 0 0.5
sox "$work/s04.wav" "$work/en.16k.wav" "$work/s08.wav" "$work/ja.16k.wav" "$work/s05.wav" \
  -b 16 "$here/voice.flac"

"""LipBlink from a live voice (issue 44, core/live_voice.h) against the offline analysis, on
recordings made here by espeak-ng and sox (tests/testing/voice_recordings.py, the takes of
test_voice_not_sound.py): the voice alone, and the issue's recording (22 s of music, 12 s of pink
and 12 s of brown noise, then the voice), at 16 and 48 kHz. tests/core/live_voice_compare runs
both analyses on a file and checks the drawing rules and that another block size gives the same
frames; here: after the first second the live speech runs are the offline ones within one grid
frame at each boundary (lookahead 3; 2 within two), and music and noise keep the mouth closed
(at most 2 % of their frames open), as offline."""
import json
import os
import subprocess
import sys

import pytest

from conftest import SERVER_BIN

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
import voice_recordings as vr  # noqa: E402  (tests/testing/voice_recordings.py)
from test_voice_not_sound import MUSIC_S, NOISE_S, TAKES  # noqa: E402

COMPARE_BIN = os.environ.get(
    "KOMA_LIVE_VOICE_COMPARE_BIN",
    os.path.join(os.path.dirname(SERVER_BIN), "..", "tests", "core", "live_voice_compare"))
FPS = 24
LEAD = int((MUSIC_S + 2 * NOISE_S) * FPS)  # grid frames of music and noise before the voice
RATES = (16000, 48000)
# Lookahead -> the largest boundary difference allowed (grid frames).
TOLERANCE = {3: 1, 2: 2}


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("live_voice"))
    music = vr.make_music(folder, MUSIC_S)
    pink = vr.make_noise(folder, "pinknoise", NOISE_S)
    brown = vr.make_noise(folder, "brownnoise", NOISE_S)
    out = {}
    for take, (sentences, silences) in TAKES.items():
        clean, _, speech_rms = vr.make_clean(folder, sentences, silences, name=f"{take}.wav")
        # The issue's recording: music as loud as the speech, the noise 6 dB less.
        levelled = [vr.mix(folder, f"{take}-{name}.level.wav", [(path, level / vr.rms(path))])
                    for name, path, level in (("music", music, speech_rms),
                                              ("pink", pink, speech_rms / 2),
                                              ("brown", brown, speech_rms / 2))]
        issue = os.path.join(folder, f"{take}-issue.wav")
        vr._concat(issue, levelled + [clean])
        for rate in RATES:
            out[f"{take}-alone@{rate}"] = vr.variant(folder, clean, f"{take}-alone@{rate}.wav",
                                                     rate=rate)
            out[f"{take}-issue@{rate}"] = vr.variant(folder, issue, f"{take}-issue@{rate}.wav",
                                                     rate=rate)
    return out


def compare(path):
    done = subprocess.run([COMPARE_BIN, path], capture_output=True, text=True, timeout=120,
                          check=True)
    return {r["lookahead"]: r for r in map(json.loads, done.stdout.splitlines())}


def cut(intervals, first):
    return [(max(b, first), e) for b, e in intervals if e > first]


def boundary_error(live, offline):
    if len(live) != len(offline):
        return None
    return max((max(abs(a[0] - b[0]), abs(a[1] - b[1])) for a, b in zip(live, offline)),
               default=0)


@pytest.mark.parametrize("take", sorted(TAKES))
@pytest.mark.parametrize("rate", RATES)
def test_live_speech_is_the_offline_speech_after_the_first_second(recordings, take, rate):
    results = compare(recordings[f"{take}-alone@{rate}"])
    for lookahead, r in results.items():
        assert r["rate"] == rate and r["rules"] == "", (lookahead, r["rules"])
    for lookahead, tolerance in TOLERANCE.items():
        r = results[lookahead]
        error = boundary_error(cut(r["live"], FPS), cut(r["offline"], FPS))
        assert error is not None and error <= tolerance, (lookahead, r["live"], r["offline"])


@pytest.mark.parametrize("take", sorted(TAKES))
@pytest.mark.parametrize("rate", RATES)
def test_music_and_noise_keep_the_mouth_closed_live_as_offline(recordings, take, rate):
    results = compare(recordings[f"{take}-issue@{rate}"])
    for lookahead, r in results.items():
        assert r["rules"] == "", (lookahead, r["rules"])
        open_live = sum(max(0, min(e, LEAD) - b) for b, e in r["live"])
        open_offline = sum(max(0, min(e, LEAD) - b) for b, e in r["offline"])
        assert open_offline == 0
        assert open_live <= 0.02 * LEAD, (lookahead, open_live, r["live"])
    # The voice after them: as on the voice alone.
    r = results[3]
    error = boundary_error(cut(r["live"], LEAD), cut(r["offline"], LEAD))
    assert error is not None and error <= TOLERANCE[3], (r["live"], r["offline"])

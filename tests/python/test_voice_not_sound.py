"""Voice, not sound (issue 44): recordings made here by espeak-ng and sox
(tests/testing/voice_recordings.py) with music-like sound (a melody with vibrato, chords with
tremolo, a plucked arpeggio, drum-like hits over a bass) and pink and brown noise, through the
real koma_server and the C++ CLI. The mouth stays closed through music and noise, and speech is
found where it is found on the voice alone: alone, after 22 s of music and 24 s of noise (the
issue's recording), over music 5, 10 and 15 dB below it, and over brown noise, at 16 and 48 kHz,
in eight espeak-ng voices (English, Japanese, German, Spanish) at 130 to 200 words a minute."""
import json
import os
import sys

import pytest

from conftest import run_cli

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
import voice_recordings as vr  # noqa: E402  (tests/testing/voice_recordings.py)

FPS = 24
# Two takes of four sentences: (voice, text, words per minute). Take A's pauses include
# 0.3 s, take B's are at least 0.5 s: over music a pause shorter than ~0.3 s may stay open
# (docs/semantics.md, "Voice, not sound"); in silence or noise the loudness closes it.
TAKES = {
    "A": ([("en-us+m3", "the quick brown fox jumps over the lazy dog", 150),
           ("ja+f3", "きょうはいいてんきですね"),
           ("en-gb+f4", "koma draws the mouth on threes", 200),
           ("en-us+m1", "a microphone hears more than a voice and so do many recordings", 170)],
          [2.0, 0.8, 1.2, 0.3, 2.0]),
    "B": ([("en-us+f2", "she sells sea shells by the sea shore", 130),
           ("de+m2", "guten morgen wie geht es dir", 160),
           ("en-gb+m4", "speech over quiet music keeps being found", 190),
           ("es+f1", "el perro come la manzana roja", 175)],
          [1.5, 0.5, 1.0, 0.6, 1.5]),
}
MUSIC_S, NOISE_S = 22.0, 12.0  # the recording: music, pink noise, brown noise, speech
LEAD_S = MUSIC_S + 2 * NOISE_S
RATES = (16000, 48000)
SHORT_PAUSE = 9  # grid frames (0.375 s): over music a shorter pause may stay open


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("voice_not_sound"))
    music = vr.make_music(folder, 30.0)
    music_rms = vr.rms(music)
    pink = vr.make_noise(folder, "pinknoise", NOISE_S)
    brown = vr.make_noise(folder, "brownnoise", NOISE_S)
    music22 = os.path.join(folder, "music22.wav")
    vr._run("sox", music, music22, "trim", "0", f"{MUSIC_S}")
    out = {}
    for take, (sentences, silences) in TAKES.items():
        clean, known, speech_rms = vr.make_clean(folder, sentences, silences, name=f"{take}.wav")
        seconds = vr._seconds(clean)
        files = {"alone": clean}
        for db in (5, 10, 15):  # the music's RMS this far below the speech's
            gain = speech_rms / music_rms / 10 ** (db / 20)
            mixed = vr.mix(folder, f"{take}-music{db}.long.wav", [(clean, 1.0), (music, gain)])
            files[f"music{db}"] = os.path.join(folder, f"{take}-music{db}.wav")
            vr._run("sox", mixed, files[f"music{db}"], "trim", "0", f"{seconds}")
        brown_long = os.path.join(folder, f"{take}-brown.noise.wav")
        vr._run("sox", "-R", "-n", "-r", str(vr.RATE), "-c", "1", "-b", "16", brown_long,
                "synth", f"{seconds}", "brownnoise", "vol", "0.5")
        # Brown noise 20 dB below the speech (at 10 dB the loudness rule itself, gate or not,
        # splits a sentence or two where a word falls into the rumble).
        files["brown20"] = vr.mix(folder, f"{take}-brown20.wav",
                                  [(clean, 1.0), (brown_long, speech_rms / 10 / vr.rms(brown_long))])
        # The recording: music and noise as loud as the speech (the noise 6 dB less).
        levelled = [vr.mix(folder, f"{take}-{name}.level.wav", [(path, level / vr.rms(path))])
                    for name, path, level in (("music", music22, speech_rms),
                                              ("pink", pink, speech_rms / 2),
                                              ("brown", brown, speech_rms / 2))]
        files["issue"] = os.path.join(folder, f"{take}-issue.wav")
        vr._concat(files["issue"], levelled + [clean])
        for name in list(files):
            for rate in RATES:
                files[f"{name}@{rate}"] = vr.variant(folder, files[name], f"{take}-{name}@{rate}.wav",
                                                     rate=rate)
        out[take] = {"known": known, "files": files}
    return out


def speech(server, tmp_path, audio):
    done = run_cli("lipblink", "--audio", audio, "-o", str(tmp_path / "out.motion3.json"),
                   "--json", "--server", server.address)
    return [(s["begin"], s["end"]) for s in json.loads(done.stdout)["voice"]["speech"]]


def frames(intervals):
    return {f for begin, end in intervals for f in range(begin, end)}


def assert_as_alone(found, alone, what, tolerance=2):
    """One found interval per interval found on the voice alone, each end within `tolerance`
    grid frames."""
    assert len(found) == len(alone), (what, found, alone)
    for f, a in zip(found, alone):
        assert abs(f[0] - a[0]) <= tolerance and abs(f[1] - a[1]) <= tolerance, (what, found, alone)


@pytest.mark.parametrize("take", sorted(TAKES))
def test_the_voice_alone_is_found_at_its_known_times(server, scenes, tmp_path, take):
    known = [(round(a * FPS), round(b * FPS)) for a, b in scenes[take]["known"]]
    for name in ("alone", *(f"alone@{rate}" for rate in RATES)):
        assert_as_alone(speech(server, tmp_path, scenes[take]["files"][name]), known, name, 1)


@pytest.mark.parametrize("take", sorted(TAKES))
def test_music_and_noise_keep_the_mouth_closed(server, scenes, tmp_path, take):
    files = scenes[take]["files"]
    lead = round(LEAD_S * FPS)  # 1104 grid frames of music and noise before the voice
    for suffix in ("", *(f"@{rate}" for rate in RATES)):
        alone = speech(server, tmp_path, files["alone" + suffix])
        found = speech(server, tmp_path, files["issue" + suffix])
        flapping = len([f for f in frames(found) if f < lead])
        assert flapping <= 0.02 * lead, (suffix, flapping, found)
        assert_as_alone([(a - lead, b - lead) for a, b in found if b > lead], alone,
                        "issue" + suffix)


@pytest.mark.parametrize("take", sorted(TAKES))
def test_speech_over_music_is_found_as_alone(server, scenes, tmp_path, take):
    files = scenes[take]["files"]
    for suffix in ("", *(f"@{rate}" for rate in RATES)):
        alone = speech(server, tmp_path, files["alone" + suffix])
        # Music alone: before the first sentence, after the last, and in the pauses between
        # them, two grid frames in from the voice's ends.
        # (A pause shorter than SHORT_PAUSE frames may stay open over music: not counted.)
        music_only = set(range(0, alone[0][0] - 2))
        for (_, end), (begin, _) in zip(alone, alone[1:]):
            if begin - end >= SHORT_PAUSE:
                music_only |= set(range(end + 2, begin - 2))
        music_only |= set(range(alone[-1][1] + 2, alone[-1][1] + 2 + 24))
        for name in ("music5", "music10", "music15", "brown20"):
            found = speech(server, tmp_path, files[name + suffix])
            flapping = len(frames(found) & music_only)
            assert flapping <= 0.02 * len(music_only), (name + suffix, flapping, found)
            if len(found) < len(alone):
                # Over music a pause shorter than SHORT_PAUSE may stay open: the sentences
                # either side of it as one (take A's 0.3 s pause).
                merged = [alone[0]]
                for begin, end in alone[1:]:
                    if begin - merged[-1][1] < SHORT_PAUSE and name.startswith("music"):
                        merged[-1] = (merged[-1][0], end)
                    else:
                        merged.append((begin, end))
                assert_as_alone(found, merged, name + suffix)
            else:
                assert_as_alone(found, alone, name + suffix)

"""Test recordings made here, never downloaded (issue 30's acceptance): Debian's espeak-ng
speaks known sentences in two voices and two languages (English, Japanese), sox joins them
with known silences, adds pink "room" noise at a given SNR, resamples, remixes the channels
and writes each format. The known speech intervals are exact: every spoken clip is trimmed
to its first and last sample above 1 % of full scale before joining.
"""
import array
import math
import os
import subprocess
import wave

RATE = 22050  # espeak-ng's own rate
# (voice, text): two voices, two languages; no punctuation, so no pause inside a sentence.
SENTENCES = [
    ("en-us+m3", "the quick brown fox jumps over the lazy dog"),
    ("ja+f3", "きょうはいいてんきですね"),
    ("en-us+f3", "koma draws the mouth on threes"),
]
# Seconds of silence before, between and after the sentences: 0.2 to 1.5 s (a pause of 0.2 s,
# 4.8 grid frames, closes the mouth when it falls to the room noise: docs/semantics.md).
SILENCES = [0.6, 1.5, 0.2, 0.8]
TRIM_LEVEL = 0.03  # of full scale: fainter tails are below the 20 dB SNR noise anyway


def _run(*args):
    subprocess.run(args, check=True, capture_output=True, timeout=60)


def _read_mono16(path):
    with wave.open(path, "rb") as w:
        assert w.getsampwidth() == 2 and w.getnchannels() == 1, path
        data = array.array("h")
        data.frombytes(w.readframes(w.getnframes()))
        return data, w.getframerate()


def _write_mono16(path, samples, rate):
    with wave.open(path, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(array.array("h", samples).tobytes())


def make_clean(folder):
    """The joined recording at 22.05 kHz 16-bit mono (folder/clean.wav), scaled to half of
    full scale so added noise never clips, and the known speech intervals in seconds."""
    os.makedirs(folder, exist_ok=True)
    pieces = []
    for i, (voice, text) in enumerate(SENTENCES):
        raw = os.path.join(folder, f"sentence{i}.wav")
        _run("espeak-ng", "-v", voice, "-w", raw, text)
        samples, rate = _read_mono16(raw)
        assert rate == RATE, rate
        level = TRIM_LEVEL * 32768
        loud = [k for k, x in enumerate(samples) if abs(x) > level]
        pieces.append(samples[loud[0]:loud[-1] + 1])
    joined = array.array("h")
    intervals = []
    for i, piece in enumerate(pieces):
        joined.extend([0] * round(SILENCES[i] * RATE))
        start = len(joined)
        joined.extend(int(x * 0.5) for x in piece)
        intervals.append((start / RATE, len(joined) / RATE))
    joined.extend([0] * round(SILENCES[-1] * RATE))
    path = os.path.join(folder, "clean.wav")
    _write_mono16(path, joined, RATE)
    speech_power = sum(float(x) * x for s, e in intervals
                       for x in joined[round(s * RATE):round(e * RATE)])
    speech_samples = sum(round(e * RATE) - round(s * RATE) for s, e in intervals)
    return path, intervals, math.sqrt(speech_power / speech_samples) / 32768


def add_noise(folder, clean, speech_rms, snr_db):
    """clean + pink noise whose RMS is snr_db below the speech's (sox synth, then mixed)."""
    noise = os.path.join(folder, f"noise{snr_db}.wav")
    duration = float(subprocess.run(["soxi", "-D", clean], check=True, capture_output=True,
                                    text=True).stdout)
    _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", noise, "synth", f"{duration}",
         "pinknoise", "vol", "0.5")
    samples, _ = _read_mono16(noise)
    rms = math.sqrt(sum(float(x) * x for x in samples) / len(samples)) / 32768
    gain = speech_rms / (10 ** (snr_db / 20)) / rms
    out = os.path.join(folder, f"noisy{snr_db}.wav")
    _run("sox", "-R", "-m", "-v", "1", clean, "-v", f"{gain:.6f}", noise, "-b", "16", out)
    return out


def variant(folder, source, name, rate=None, channels=None, sox_format=()):
    """`source` resampled / remixed / re-encoded by sox as folder/name."""
    out = os.path.join(folder, name)
    effects = []
    if rate:
        effects += ["rate", "-h", str(rate)]
    if channels:
        effects += ["channels", str(channels)]
    _run("sox", "-R", source, *sox_format, out, *effects)
    return out


def opus(folder, source, name):
    """Ogg Opus through libsndfile's own converter (sox cannot write Opus; Opus takes 8, 12,
    16, 24 or 48 kHz, so the source is resampled to 48 kHz first)."""
    at48 = variant(folder, source, name + ".48k.wav", rate=48000)
    out = os.path.join(folder, name)
    _run("sndfile-convert", "-opus", at48, out)
    return out

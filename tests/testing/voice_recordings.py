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


def make_clean(folder, sentences=SENTENCES, silences=SILENCES, name="clean.wav"):
    """The joined recording at 22.05 kHz 16-bit mono (folder/name), scaled to half of
    full scale so added noise never clips, and the known speech intervals in seconds.
    `sentences` are (voice, text) or (voice, text, words per minute: espeak-ng's -s, 175 by
    default); `silences` one more than them."""
    os.makedirs(folder, exist_ok=True)
    pieces = []
    for i, (voice, text, *speed) in enumerate(sentences):
        raw = os.path.join(folder, f"{name}.sentence{i}.wav")
        _run("espeak-ng", "-v", voice, *(["-s", str(speed[0])] if speed else []), "-w", raw, text)
        samples, rate = _read_mono16(raw)
        assert rate == RATE, rate
        level = TRIM_LEVEL * 32768
        loud = [k for k, x in enumerate(samples) if abs(x) > level]
        pieces.append(samples[loud[0]:loud[-1] + 1])
    joined = array.array("h")
    intervals = []
    for i, piece in enumerate(pieces):
        joined.extend([0] * round(silences[i] * RATE))
        start = len(joined)
        joined.extend(int(x * 0.5) for x in piece)
        intervals.append((start / RATE, len(joined) / RATE))
    joined.extend([0] * round(silences[-1] * RATE))
    path = os.path.join(folder, name)
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


# Sounds that are not a voice (issue 44, "Voice, not sound"), all from sox's synth: music-like
# sections of a few seconds each (a sawtooth melody with a 5.5 Hz vibrato of about 1.5 %,
# triangle chords with a 4 Hz tremolo, a plucked arpeggio, drum-like noise hits over a square
# bass), cycled to the length asked for; pink and brown noise.
MELODY = [0, 2, 4, 5, 7, 9, 7, 5, 4, 2, 0, -3]  # semitones from A440, 0.45 s each
CHORDS = [(-12, -8, -5), (-7, -3, 0), (-9, -5, -2), (-10, -7, -3)]  # 1.4 s each
ARPEGGIO = [-12, -8, -5, 0, -5, -8, -10, -7, -3, 2, -3, -7, -14, -10, -7, -2, -7, -10]  # 0.3 s


def _seconds(path):
    return float(subprocess.run(["soxi", "-D", path], check=True, capture_output=True,
                                text=True).stdout)


def _synth(out, seconds, *args):
    _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", out, "synth",
         f"{seconds}", *args)


def _concat(out, parts):
    _run("sox", "-R", *parts, "-b", "16", out)


def _music_sections(folder):
    sections = []
    melody = []
    for k, n in enumerate(MELODY):  # vibrato: a 5.5 Hz sine frequency-modulating the note
        note = os.path.join(folder, f"melody{k}.wav")
        _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", note,
             "synth", "0.45", "sine", "5.5", "vol", "0.03",
             "synth", "0.45", "sawtooth", "fmod", f"%{n}", "fade", "0.02", "0.45", "0.05")
        melody.append(note)
    sections.append(os.path.join(folder, "melody.wav"))
    _concat(sections[-1], melody)
    chords = []
    for k, chord in enumerate(CHORDS):  # three triangles mixed, a 4 Hz tremolo of depth 50
        tones = os.path.join(folder, f"chord{k}.3.wav")
        _run("sox", "-R", "-n", "-r", str(RATE), "-c", "3", "-b", "16", tones, "synth", "1.4",
             *[x for n in chord for x in ("triangle", f"%{n}")])
        chords.append(os.path.join(folder, f"chord{k}.wav"))
        _run("sox", "-R", tones, "-b", "16", chords[-1], "remix", "1-3", "tremolo", "4", "50",
             "fade", "0.02", "1.4", "0.05")
    sections.append(os.path.join(folder, "chords.wav"))
    _concat(sections[-1], chords)
    plucks = []
    for k, n in enumerate(ARPEGGIO):
        plucks.append(os.path.join(folder, f"pluck{k}.wav"))
        _synth(plucks[-1], 0.3, "pluck", f"%{n}")
    sections.append(os.path.join(folder, "arpeggio.wav"))
    _concat(sections[-1], plucks)
    # Drums: a brown-noise kick and a white-noise snare, 0.25 s apart, over a square bass.
    kick, snare = os.path.join(folder, "kick.wav"), os.path.join(folder, "snare.wav")
    _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", kick, "synth", "0.12",
         "brownnoise", "fade", "q", "0.002", "0.12", "0.11", "pad", "0", "0.13")
    _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", snare, "synth", "0.08",
         "whitenoise", "vol", "0.5", "fade", "q", "0.002", "0.08", "0.07", "pad", "0", "0.17")
    beat = os.path.join(folder, "beat.wav")
    _concat(beat, [kick, snare] * 12)
    bass = os.path.join(folder, "bass.wav")
    _synth(bass, 6.0, "square", "%-31", "vol", "0.3")
    sections.append(os.path.join(folder, "drums.wav"))
    _run("sox", "-R", "-m", beat, bass, "-b", "16", sections[-1])
    return sections


def make_music(folder, seconds, name="music.wav"):
    """folder/name: the music-like sections in turn, cycled and cut to `seconds`."""
    os.makedirs(folder, exist_ok=True)
    sections = _music_sections(folder)
    parts, total = [], 0.0
    while total < seconds:
        for section in sections:
            parts.append(section)
            total += _seconds(section)
    out = os.path.join(folder, name)
    _run("sox", "-R", *parts, "-b", "16", out, "trim", "0", f"{seconds}")
    return out


def make_noise(folder, kind, seconds, name=None):
    """folder/name: `kind` ('pinknoise' or 'brownnoise') from sox's synth."""
    out = os.path.join(folder, name or f"{kind}.wav")
    _synth(out, seconds, kind, "vol", "0.5")
    return out


def rms(path, begin=0.0, end=None):
    """The RMS of a 16-bit mono WAV from `begin` to `end` seconds, in full scale."""
    samples, rate = _read_mono16(path)
    piece = samples[round(begin * rate):None if end is None else round(end * rate)]
    return math.sqrt(sum(float(x) * x for x in piece) / max(len(piece), 1)) / 32768


def mix(folder, name, tracks):
    """folder/name: (path, gain) tracks summed sample by sample (sox -m), the shortest padded
    with silence."""
    out = os.path.join(folder, name)
    args = []
    for path, gain in tracks:
        args += ["-v", f"{gain:.6f}", path]
    _run("sox", "-R", *(["-m"] if len(tracks) > 1 else []), *args, "-b", "16", out)
    return out


def silence(folder, seconds, name):
    out = os.path.join(folder, name)
    _run("sox", "-R", "-n", "-r", str(RATE), "-c", "1", "-b", "16", out, "trim", "0",
         f"{seconds}")
    return out

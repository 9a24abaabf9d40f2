"""Audio for a live stream: a file played at real time, or the microphone through ALSA.

koma.AudioFile(path): WAV through the stdlib `wave` module (integer PCM); other formats (FLAC,
Ogg, MP3, float WAV) decoded by `sox FILE -t raw ...` (Debian package sox) when it is on PATH.
As the C++ `koma live` (client/live_audio_source.cc): 8- and 16-bit PCM is sent as "s16le",
anything else as "f32le". koma.Microphone(device): `arecord` (Debian package alsa-utils),
16-bit mono at 48 kHz. Both give .sample_rate, .channels, .sample_format and
.chunks(chunk_ms, speed, seconds, stop): little-endian chunks of whole sample frames, a
recording's paced by time.monotonic (a sound card paces itself).
"""
import array
import shutil
import subprocess
import sys
import time
import wave

S16 = "s16le"
F32 = "f32le"
_PCM16_ENCODINGS = ("Signed Integer PCM", "Unsigned Integer PCM", "FLAC")  # sox --i -e


class AudioSourceError(OSError):
    """A recording or a device that cannot be read (a missing tool, an unreadable file)."""


class _Source:
    description = ""  # what the audio is, for the CLI's first line
    sample_rate = 0
    channels = 0
    sample_format = S16
    # Pace chunks at real time: a file does; a microphone's reads block at real time anyway,
    # but ALSA's null device hands out its samples at once.
    paced = True

    def _read(self, frames):
        """Up to `frames` sample frames of 16-bit little-endian interleaved samples; b"" at
        the end."""
        raise NotImplementedError

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def chunks(self, chunk_ms=10, speed=1.0, seconds=None, stop=None):
        """The audio in chunks of chunk_ms milliseconds, each given when its end is due:
        at real time with speed 1, twice as fast with 2, at once with 0. seconds: stop after
        that much audio. stop: a threading.Event that ends the chunks when set."""
        if not chunk_ms > 0:
            raise ValueError(f"chunk_ms: {chunk_ms!r} must be > 0")
        if speed < 0:
            raise ValueError(f"speed: {speed!r} must be >= 0 (0: as fast as the server reads)")
        frames_per_chunk = max(1, round(self.sample_rate * chunk_ms / 1000.0))
        limit = None if seconds is None else max(0, round(seconds * self.sample_rate))
        frame_bytes = (2 if self.sample_format == S16 else 4) * self.channels
        sent = 0
        start = time.monotonic()
        try:
            while limit is None or sent < limit:
                if stop is not None and stop.is_set():
                    return
                want = frames_per_chunk if limit is None else min(frames_per_chunk, limit - sent)
                data = self._read(want)
                data = data[:len(data) - len(data) % frame_bytes]
                if not data:
                    return
                sent += len(data) // frame_bytes
                if speed > 0 and self.paced:
                    due = start + sent / self.sample_rate / speed
                    delay = due - time.monotonic()
                    if delay > 0:
                        if stop is not None:
                            if stop.wait(delay):
                                return
                        else:
                            time.sleep(delay)
                yield data
        finally:
            self.close()


def _to_f32(data, width):
    """Little-endian integer PCM of 3 or 4 bytes per sample as 32-bit floats (full scale 1),
    as libsndfile reads it."""
    ints = bytearray(len(data) // width * 4)
    for k in range(width):
        ints[4 - width + k::4] = data[k::width]
    values = array.array("i", bytes(ints))
    if sys.byteorder != "little":
        values.byteswap()
    floats = array.array("f", [v * (1.0 / 2147483648.0) for v in values])
    if sys.byteorder != "little":
        floats.byteswap()
    return floats.tobytes()


def _to_s16(data, width):
    """Little-endian integer PCM of `width` bytes per sample as 16-bit (its top two bytes)."""
    if width == 2:
        return bytes(data)
    out = bytearray(len(data) // width * 2)
    if width == 1:  # WAV's 8-bit is unsigned
        out[1::2] = bytes(data).translate(bytes((b ^ 0x80) for b in range(256)))
    else:
        out[0::2] = data[width - 2::width]
        out[1::2] = data[width - 1::width]
    return bytes(out)


class _Wav(_Source):
    def __init__(self, path, reader):
        self.path = path
        self._reader = reader
        self.sample_rate = reader.getframerate()
        self.channels = reader.getnchannels()
        self._width = reader.getsampwidth()
        self.sample_format = S16 if self._width <= 2 else F32
        self.description = f"{path}: WAV, {8 * self._width}-bit PCM (Python's wave)"

    def _read(self, frames):
        data = self._reader.readframes(frames)
        return _to_s16(data, self._width) if self._width <= 2 else _to_f32(data, self._width)

    def close(self):
        self._reader.close()


class _Process(_Source):
    """The raw 16-bit output of a decoding or capturing process."""

    def __init__(self, argv, what):
        self._what = what
        try:
            self._process = subprocess.Popen(argv, stdout=subprocess.PIPE,
                                             stderr=subprocess.PIPE, stdin=subprocess.DEVNULL)
        except OSError as error:
            raise AudioSourceError(f"{what}: cannot run {argv[0]}: {error}") from None

    def _read(self, frames):
        data = self._process.stdout.read(frames * (2 if self.sample_format == S16 else 4) *
                                         self.channels)
        if not data:
            self._check_exit()
        return data

    def _check_exit(self):
        code = self._process.wait()
        if code != 0:
            message = self._process.stderr.read().decode("utf-8", "replace").strip()
            raise AudioSourceError(f"{self._what}: exited with status {code}: {message}")

    def close(self):
        # The pipe first: a process blocked writing to it (arecord ignores SIGTERM then) gets
        # EPIPE and ends.
        self._process.stdout.close()
        if self._process.poll() is None:
            self._process.terminate()
            try:
                self._process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        self._process.stderr.close()


def _sox_info(sox, path, flag, number=True):
    done = subprocess.run([sox, "--i", flag, path], capture_output=True, text=True)
    if done.returncode != 0 or (number and not done.stdout.strip().isdigit()):
        raise AudioSourceError(f"{path}: sox cannot read it: {done.stderr.strip()}")
    return int(done.stdout.strip()) if number else done.stdout.strip()


class _Sox(_Process):
    def __init__(self, path, sox):
        self.path = path
        self.sample_rate = _sox_info(sox, path, "-r")
        self.channels = _sox_info(sox, path, "-c")
        encoding = _sox_info(sox, path, "-e", number=False)
        pcm16 = _sox_info(sox, path, "-b") in (8, 16) and encoding in _PCM16_ENCODINGS
        self.sample_format = S16 if pcm16 else F32
        self.description = f"{path}: {encoding}, decoded by sox"
        raw = ["-e", "signed-integer", "-b", "16"] if pcm16 else ["-e", "floating-point", "-b",
                                                                   "32"]
        # -D: no dither (sox adds it when it reduces the precision).
        super().__init__([sox, "-q", "-D", path, "-t", "raw", *raw, "-L", "-"],
                         f"sox decoding {path}")


def AudioFile(path):
    """A recording to play into a live stream: a WAV (integer PCM) through `wave`, any other
    format sox reads (FLAC, Ogg Vorbis, MP3, float WAV) through sox when it is on PATH.
    Its .chunks() are at the file's rate and channels, "s16le" for 8- and 16-bit PCM,
    "f32le" otherwise (.sample_format). Raises
    AudioSourceError (an OSError) naming what is missing."""
    path = str(path)
    with open(path, "rb"):
        pass  # a missing or unreadable file: the OSError names it
    try:
        return _Wav(path, wave.open(path, "rb"))
    except (wave.Error, EOFError) as error:
        why = str(error)
    sox = shutil.which("sox")
    if sox is None:
        raise AudioSourceError(
            f"{path}: not a WAV file Python's wave module reads ({why}); decoding it (FLAC, Ogg, "
            "MP3, float WAV) needs sox, which is not on PATH: install the Debian package sox, "
            "or convert the file to a 16-bit WAV")
    return _Sox(path, sox)


class Microphone(_Process):
    """The microphone through ALSA's `arecord` (Debian package alsa-utils): 16-bit, `channels`
    channels at `sample_rate`, from `device` ("default"; "null" gives samples without a
    sound card). Reads block at the card's rate (ALSA's null device's do not: chunks() paces
    it)."""

    def __init__(self, device="default", sample_rate=48000, channels=1):
        arecord = shutil.which("arecord")
        if arecord is None:
            raise AudioSourceError("the microphone needs arecord, which is not on PATH: install "
                                   "the Debian package alsa-utils (or play a file: --input FILE)")
        self.device = device
        # A sound card's clock paces its reads, and drifts from the computer's: pacing it
        # by time.monotonic would overrun its buffer within minutes. ALSA's null device
        # answers at once, so it is paced.
        self.paced = device == "null"
        self.sample_rate = int(sample_rate)
        self.channels = int(channels)
        self.description = f"ALSA device {device} (arecord)"
        super().__init__([arecord, "-q", "-D", device, "-f", "S16_LE", "-r",
                          str(self.sample_rate), "-c", str(self.channels), "-t", "raw"],
                         f"arecord -D {device}")

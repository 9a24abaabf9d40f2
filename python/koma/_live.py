"""Client.live: LipBlink from a live voice (the LiveLipBlink bidirectional stream).

The requests (the setup, then the audio chunks) go out from gRPC's own thread as the caller's
chunk iterator gives them; the frames come back to the caller's thread as the server decides
them (one per film-grid frame, in order from 0). docs/python.md, "Live".
"""
import collections
import math
import threading
import time

import grpc

from koma import _options
from koma._errors import KomaError
from koma.v1 import retime_pb2

SAMPLE_FORMATS = {"s16le": retime_pb2.LIVE_SAMPLE_S16LE, "f32le": retime_pb2.LIVE_SAMPLE_F32LE}
_SHAPES = {retime_pb2.MOUTH_CLOSED: "closed", retime_pb2.MOUTH_MID: "half",
           retime_pb2.MOUTH_OPEN: "open"}
# Audio sent ahead of the frames read back, at most (seconds): the server ends a stream whose
# client reads none of its last --live_max_queued_frames (240: 10 s at 24 fps), so a caller that
# sends faster than real time (a file at speed 0) or reads slowly waits here instead.
MAX_AHEAD_S = 4.0

# The fields of a frame's JSON line, in the C++ `koma live --json`'s order
# (client/live_output.cc).
JSON_FIELDS = ("grid_frame", "time_s", "speech", "mouth", "mouth_level", "new_drawing",
               "hold_start", "eyes", "blink", "blink_start", "eye_level", "loudness_dbfs",
               "noise_floor_dbfs", "late_ms", "wall_late_ms", "wall_s")


class LiveFrame:
    """One decided film-grid frame of a live stream (koma.v1.LiveLipBlinkFrame).

    Attributes:
        grid_frame: its number, from 0; it covers [grid_frame, grid_frame + 1) / timing_fps
            seconds of the audio.
        time_s: its start, seconds of audio from the stream's first sample.
        mouth: the mouth drawing, "closed", "half" or "open".
        mouth_level: the value to write for it (the mouth settings' min, mid or max).
        speech: True in speech, False in a pause (the mouth closed).
        blink: True while the eyes are not open (an auto-blink's half or closed drawing).
        eyes: the eyes' drawing, "open", "half" or "closed".
        eye_level: the value to write for them (the eye settings' max, mid or min).
        new_drawing: the mouth's drawing differs from the previous frame's.
        hold_start: a mouth hold starts here (speech only).
        blink_start: an auto-blink closes the eyes here.
        late_ms: milliseconds of audio past the frame's end the server had when it decided
            it (the lookahead; less at the stream's end).
        loudness_dbfs, noise_floor_dbfs: the frame's RMS and the running noise floor, dBFS.
        wall_late_ms: milliseconds from sending the audio chunk that completed the frame's
            audio to receiving the frame (the lookahead plus the chunk, the transport and the
            analysis; after the audio ended, from the last chunk).
        wall_s: seconds from the stream's start to receiving the frame.
        message: the koma.v1.LiveLipBlinkFrame itself.
    """

    __slots__ = ("grid_frame", "time_s", "mouth", "mouth_level", "speech", "blink", "eyes",
                 "eye_level", "new_drawing", "hold_start", "blink_start", "late_ms",
                 "loudness_dbfs", "noise_floor_dbfs", "wall_late_ms", "wall_s", "message")

    def __init__(self, message, wall_late_ms=0.0, wall_s=0.0):
        self.message = message
        self.grid_frame = message.grid_frame
        self.time_s = message.time_s
        self.mouth = _SHAPES.get(message.mouth, "closed")
        self.mouth_level = message.mouth_level
        self.speech = message.speech
        self.eyes = _SHAPES.get(message.eyes, "closed")
        self.blink = message.eyes != retime_pb2.MOUTH_OPEN
        self.eye_level = message.eye_level
        self.new_drawing = message.new_drawing
        self.hold_start = message.hold_start
        self.blink_start = message.blink_start
        self.late_ms = message.late_ms
        self.loudness_dbfs = message.loudness_dbfs
        self.noise_floor_dbfs = message.noise_floor_dbfs
        self.wall_late_ms = round(wall_late_ms, 3)  # as `koma live`: to 0.001 ms
        self.wall_s = round(wall_s, 6)

    def to_dict(self):
        """The frame's JSON line, as `koma live --json` writes it (JSON_FIELDS, in order)."""
        return {name: getattr(self, name) for name in JSON_FIELDS}

    def __repr__(self):
        return (f"LiveFrame(grid_frame={self.grid_frame}, mouth={self.mouth!r}, "
                f"speech={self.speech}, eyes={self.eyes!r}, late_ms={self.late_ms:.1f})")


def check_chunks(audio_chunks):
    """TypeError for one buffer given where chunks are expected (its bytes would be ints)."""
    if isinstance(audio_chunks, (bytes, bytearray, memoryview, str)) or \
            not hasattr(audio_chunks, "__iter__"):
        raise TypeError("audio_chunks: expected an iterable of byte chunks (e.g. 10 ms each), "
                        f"got {type(audio_chunks).__name__}; pass [data] to send one buffer")


def setup_request(sample_rate, channels, sample_format, lookahead, seed, options):
    """The stream's first message. Wrong option names and types raise here (TypeError,
    ValueError); values out of range come back from the server as a KomaError naming the
    setup's field (setup.sample_rate, setup.channels, ...)."""
    if sample_format not in SAMPLE_FORMATS:
        raise ValueError(f"sample_format: {sample_format!r} is not one of "
                         f"{', '.join(SAMPLE_FORMATS)}")
    request = retime_pb2.LiveLipBlinkRequest()
    setup = request.setup
    _options.fill(setup, {"sample_rate": sample_rate, "channels": channels,
                          "lookahead_frames": lookahead, "seed": seed})
    setup.sample_format = SAMPLE_FORMATS[sample_format]
    _options.fill(setup, options, skip=("sample_rate", "channels", "sample_format",
                                        "lookahead_frames", "seed"))
    return request


class _Pacer:
    """Holds the request thread back while the audio sent is MAX_AHEAD_S ahead of the frames
    read; wakes it when the caller stops reading."""

    def __init__(self, sample_rate, channels, bytes_per_sample, fps):
        self._rate = max(1, sample_rate)
        self._frame_bytes = max(1, channels) * bytes_per_sample
        self._fps = fps if fps and fps > 0 else 24.0
        self._sent_frames = 0
        self._read_s = 0.0
        self._stopped = False
        self._cv = threading.Condition()
        # (sample frames sent after a chunk, when it was sent), for LiveFrame.wall_late_ms.
        self._log = collections.deque()
        self.start = time.monotonic()

    def sending(self, byte_count):
        """Notes a chunk about to be sent, and when."""
        with self._cv:
            self._sent_frames += byte_count // self._frame_bytes
            self._log.append((self._sent_frames, time.monotonic()))

    def wait(self):
        """Waits while the audio sent is MAX_AHEAD_S ahead; False when the stream is over."""
        with self._cv:
            while not self._stopped and \
                    self._sent_frames / self._rate - self._read_s > MAX_AHEAD_S:
                self._cv.wait(0.5)
            return not self._stopped

    def read(self, message):
        """(wall_late_ms, wall_s) of a frame just received."""
        now = time.monotonic()
        with self._cv:
            self._read_s = (message.grid_frame + 1) / self._fps
            self._cv.notify_all()
            # The chunk completing the frame's audio (the last one when the audio ended first).
            end = math.ceil((message.time_s + 1.0 / self._fps) * self._rate - 1e-6)
            while len(self._log) > 1 and self._log[0][0] < end:
                self._log.popleft()
            sent_at = self._log[0][1] if self._log else None
        return (0.0 if sent_at is None else (now - sent_at) * 1000.0), now - self.start

    def stop(self):
        with self._cv:
            self._stopped = True
            self._cv.notify_all()

    @property
    def stopped(self):
        return self._stopped


def _close(chunks):
    """Closes a chunk generator (and so its source), unless another thread is inside it (then
    it ends when that thread leaves it)."""
    close = getattr(chunks, "close", None)
    if close is not None:
        try:
            close()
        except Exception:  # noqa: BLE001  (ValueError: generator already executing)
            pass


def stream(stub, setup, audio_chunks, timeout, metadata=None):
    """Runs the call: a generator of LiveFrame. Raises KomaError when the server ends the
    stream with an error, and re-raises what the caller's chunk iterator raised."""
    fields = setup.setup
    pacer = _Pacer(fields.sample_rate, fields.channels,
                   2 if fields.sample_format == retime_pb2.LIVE_SAMPLE_S16LE else 4,
                   fields.timing_fps if fields.HasField("timing_fps") else 24.0)
    failure = []

    def requests():
        yield setup
        try:
            for chunk in audio_chunks:
                if pacer.stopped:
                    return
                if not isinstance(chunk, (bytes, bytearray, memoryview)):
                    raise TypeError(f"audio_chunks: expected chunks of bytes, got "
                                    f"{type(chunk).__name__}")
                data = bytes(chunk)
                pacer.sending(len(data))
                yield retime_pb2.LiveLipBlinkRequest(audio=data)
                if not pacer.wait():
                    return
        except Exception as error:  # noqa: BLE001  (re-raised in the caller's thread)
            failure.append(error)
            call.cancel()
        finally:
            _close(audio_chunks)

    call = stub.LiveLipBlink(requests(), timeout=timeout, metadata=metadata)
    try:
        for message in call:
            yield LiveFrame(message, *pacer.read(message))
    except grpc.RpcError as error:
        if failure:
            raise failure[0]
        raise KomaError.from_rpc_error(error) from None
    finally:
        pacer.stop()
        call.cancel()  # the caller stopped reading early: end the stream (no-op when done)
        _close(audio_chunks)  # a file's decoder or the microphone, now rather than at GC
    if failure:
        raise failure[0]

"""`python3 -m koma live`: LipBlink from a live voice (the LiveLipBlink stream), as the C++
`koma live`: a file played at real time (--input) or the microphone (ALSA's arecord), the
frames as JSON lines (--json), VMC blend shapes (--vmc), VTube Studio's plugin API (--vts) and
a motion3.json (--record).

    python3 -m koma live [--input FILE] [--device DEV] [--json] [--vmc [HOST:PORT]] [--vts [URL]]
        [--seconds S] [--speed X] [--lookahead N] [--record OUT.motion3.json] ...
"""
import argparse
import json
import math
import os
import signal
import sys
import threading

from koma import _live_sources
from koma._live_record import Motion3Recorder
from koma._vmc import VmcSender, levels, parse_target

MIC_RATE = 48000


def _lookahead(text):
    value = int(text)
    if not 0 <= value <= 3:
        raise argparse.ArgumentTypeError(f"{text} must be 0, 1, 2 or 3 (grid frames)")
    return value


def _not_negative(text):
    value = float(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"{text} must be >= 0")
    return value


def add_parser(commands, common):
    """The subcommand's flags: the C++ `koma live`'s names (client/live_flags.cc), a subset."""
    p = commands.add_parser(
        "live", help="mouth flaps and blinks from a live voice (LiveLipBlink)",
        description="Streams a voice to the server and gets one frame per 24 fps grid frame "
                    "back as soon as it is decided: from a file played at real time "
                    "(--input), else the microphone through ALSA's arecord.")
    p.add_argument("--input", metavar="FILE",
                   help="a recording played at real time: WAV, or FLAC, Ogg, MP3 through sox "
                        "(default: the microphone)")
    p.add_argument("--device",
                   help="the microphone's ALSA device, 48 kHz mono (arecord -D; default "
                        "\"default\"; \"null\" for no sound card)")
    p.add_argument("--seconds", type=_not_negative,
                   help="stop after this many seconds of audio (default: the whole file, or "
                        "until Ctrl-C)")
    p.add_argument("--speed", type=_not_negative,
                   help="--input: play at this many times real time (default 1; 0: as fast "
                        "as the stream takes it)")
    p.add_argument("--lookahead", "--lookahead-frames", type=_lookahead, default=2,
                   help="grid frames the server waits past a frame before deciding it, 0-3 "
                        "(default 2; each 41.7 ms)")
    p.add_argument("--mode", "--mouth-mode", choices=["random", "follow"],
                   help="mouth drawings: random (the paper, default) or follow the loudness")
    p.add_argument("--on", "--mouth-frames-per-shape", type=int,
                   help="grid frames each mouth drawing is held (default 3)")
    p.add_argument("--mouth-min", type=float, help="the closed mouth level (default 0)")
    p.add_argument("--mouth-max", type=float,
                   help="the open mouth level (default max(1, --mouth-min + 1))")
    p.add_argument("--eyes-min", type=float, help="the closed eye level (default 0)")
    p.add_argument("--eyes-max", type=float, help="the open eye level (default 1)")
    p.add_argument("--auto-blink", type=float, metavar="MEAN_S",
                   help="blink every MEAN_S seconds on average (default: the eyes stay open)")
    p.add_argument("--voice-settings-any-sound", action="store_true",
                   help="speech by loudness alone (singing, a synthesised voice)")
    p.add_argument("--seed", type=int, help="seed of the random mouth shapes and auto-blinks")
    p.add_argument("--timing-fps", type=float, help="film grid in frames per second (default 24)")
    p.add_argument("--record", metavar="OUT.motion3.json",
                   help="write the frames as a motion3.json (ParamMouthOpenY, ParamEyeLOpen, "
                        "ParamEyeROpen stepped on the grid) when the stream ends")
    p.add_argument("--vmc", nargs="?", const="", metavar="HOST:PORT",
                   help="send VMC blend shapes per frame over OSC/UDP (default "
                        "127.0.0.1:39539; needs python3-liblo)")
    p.add_argument("--vmc-mouth-clip", default="A",
                   help="VRM blend shape clip of the open mouth (default A; VRM 1.0: aa)")
    p.add_argument("--vmc-blink-clip", default="Blink",
                   help="VRM blend shape clip of the closed eyes (default Blink; VRM 1.0: "
                        "blink)")
    p.add_argument("--vts", nargs="?", const="", metavar="URL",
                   help="inject each frame into VTube Studio through its plugin API at URL "
                        "(default ws://localhost:8001; needs python3-websockets)")
    p.add_argument("--vts-token-file", metavar="FILE",
                   help="where the token VTube Studio gave koma is kept (default "
                        "$XDG_CONFIG_HOME/koma/vts-token, or ~/.config/koma/vts-token)")
    p.add_argument("--vts-mouth-param", metavar="NAME", default="MouthOpen",
                   help="VTube Studio input parameter of the mouth, 0 closed .. 1 open "
                        "(default MouthOpen)")
    p.add_argument("--vts-eye-left-param", metavar="NAME", default="EyeOpenLeft",
                   help="VTube Studio input parameter of the left eye, 0 shut .. 1 open "
                        "(default EyeOpenLeft)")
    p.add_argument("--vts-eye-right-param", metavar="NAME", default="EyeOpenRight",
                   help="VTube Studio input parameter of the right eye, 0 shut .. 1 open "
                        "(default EyeOpenRight)")
    p.add_argument("--json", action="store_true",
                   help="one JSON object per frame on stdout, as `koma live --json`; the human "
                        "lines go to stderr")
    p.add_argument("-q", "--quiet", action="store_true", help="no human lines or summary")
    common(p, deadline=None)
    # As `koma live --deadline`: 0 is none too.
    deadline = next(a for a in p._actions if "--deadline" in a.option_strings)
    deadline.type, deadline.help = _not_negative, "end the stream after this many seconds " \
        "(default 0: none)"


class _Usage(Exception):
    pass


def _source(args):
    """The audio source; its errors as the C++ `koma live` words them."""
    if args.input is not None:
        if args.device is not None:
            raise _Usage(f"--input {args.input} and --device {args.device}: give one audio "
                         "source")
        try:
            return _live_sources.AudioFile(args.input)
        except _live_sources.AudioSourceError as error:
            why = str(error)
            why = why[len(args.input) + 2:] if why.startswith(f"{args.input}: ") else why
            raise OSError(f"--input {args.input}: {why}") from None
        except OSError as error:
            raise OSError(f"--input {args.input}: cannot read {args.input}: "
                          f"{error.strerror or error}") from None
    if args.speed is not None:
        raise _Usage("--speed: only with --input (the microphone is real time)")
    return _live_sources.Microphone(args.device or "default", MIC_RATE, 1)


def _write_line(out, text):
    """Writes and flushes a line; False when its reader has gone (then it points at
    /dev/null, so the interpreter's own flush at exit does not fail)."""
    try:
        out.write(text + "\n")
        out.flush()
        return True
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), out.fileno())
        return False


class _Text:
    """The human lines, as the C++ `koma live` writes them: one per second of audio, then a
    summary."""

    def __init__(self, out, fps):
        self.out, self.fps = out, fps
        self.frames = self.speech = self.runs = self.drawings = self.blinks = 0
        self.in_speech = False
        self.late_ms = 0.0
        self.wall = []
        self.second = []

    def frame(self, f):
        self.frames += 1
        if f.speech and not self.in_speech:
            self.runs += 1
        self.in_speech = f.speech
        self.speech += f.speech
        self.drawings += f.new_drawing
        self.blinks += f.blink_start
        self.late_ms = max(self.late_ms, f.late_ms)
        self.wall.append(f.wall_late_ms)
        self.second.append(f)
        end_s = (f.grid_frame + 1) / self.fps
        if math.floor(end_s + 1e-9) > math.floor(f.grid_frame / self.fps + 1e-9):
            return self._flush(end_s)
        return True

    def _flush(self, end_s):
        s = self.second
        self.second = []
        wall = [f.wall_late_ms for f in s]
        return _write_line(self.out, (
            f"{end_s:7.1f} s  speech {sum(f.speech for f in s):2d}/{len(s)} frames, "
            f"{sum(f.new_drawing for f in s)} new drawings, {sum(f.blink_start for f in s)} "
            f"blinks; received {sum(wall) / len(s):.0f} ms after the audio (max "
            f"{max(wall):.0f})"))

    def close(self):
        if self.second:
            self._flush(self.frames / self.fps)
        wall = sorted(self.wall)
        median = wall[len(wall) // 2] if wall else 0.0
        _write_line(self.out, (
            f"koma live: {self.frames} frames ({self.frames / self.fps:.2f} s at "
            f"{self.fps:g} fps): speech in {self.speech} frames ({self.runs} runs), "
            f"{self.drawings} new mouth drawings, {self.blinks} blinks; decided "
            f"{self.late_ms:.1f} ms after a frame's end (lookahead), received {median:.1f} ms "
            f"after its audio was sent (median; max {wall[-1] if wall else 0.0:.1f})"))


def _settings(args):
    mode = {"random": "MOUTH_RANDOM", "follow": "MOUTH_FOLLOW"}.get(args.mode)
    auto = {"enabled": True, "mean_interval_s": args.auto_blink} \
        if args.auto_blink is not None else None
    return dict(
        lookahead=args.lookahead, seed=args.seed, timing_fps=args.timing_fps,
        mouth={"mode": mode, "frames_per_shape": args.on, "min": args.mouth_min,
               "max": args.mouth_max},
        eyes={"min": args.eyes_min, "max": args.eyes_max, "auto_blink": auto},
        voice_settings={"any_sound": True} if args.voice_settings_any_sound else None,
        timeout=args.deadline or None)


def run(args, make_client):
    """The subcommand; returns the exit status (KomaError and OSError reach main())."""
    try:
        vmc = vts = None
        mouth, eyes = levels(args.mouth_min, args.mouth_max, args.eyes_min, args.eyes_max)
        for flag, name in (("--vts-mouth-param", args.vts_mouth_param),
                           ("--vts-eye-left-param", args.vts_eye_left_param),
                           ("--vts-eye-right-param", args.vts_eye_right_param)):
            if not name:
                raise _Usage(f"{flag} must not be empty")
        if args.vts is not None:
            from koma._vts import parse_url  # noqa: PLC0415  (only with --vts)
            try:
                parse_url(args.vts or "ws://localhost:8001")  # a usage error, before the rest
            except ValueError as error:
                raise _Usage(f"--vts: {error}") from None
        if args.vmc is not None:
            vmc = VmcSender(*parse_target(args.vmc), mouth_range=mouth, eye_range=eyes,
                            mouth_clip=args.vmc_mouth_clip, blink_clip=args.vmc_blink_clip)
        if args.vts is not None:
            from koma._vts import VtsSender  # noqa: PLC0415  (imports websockets)
            vts = VtsSender(args.vts, args.vts_token_file, mouth_range=mouth, eye_range=eyes,
                            mouth_param=args.vts_mouth_param,
                            eye_left_param=args.vts_eye_left_param,
                            eye_right_param=args.vts_eye_right_param)
        source = _source(args)
    except (ValueError, _Usage) as error:
        sys.stderr.write(f"koma: {error}\n")
        return 2
    except ImportError as error:
        sys.stderr.write(f"koma: {error}\n")
        return 1
    if vts is not None:
        # As `koma live`: connected and authenticated (the popup answered) before any audio.
        from koma._vts import VtsError  # noqa: PLC0415
        try:
            vts.start()
        except VtsError as error:
            source.close()
            sys.stderr.write(f"koma: {error}\n")
            return 1
        except KeyboardInterrupt:  # Ctrl-C while VTube Studio's popup waits for an answer
            source.close()
            return 130
        except BaseException:
            source.close()
            raise
    fps = args.timing_fps or 24.0
    text = None if args.quiet else _Text(sys.stderr if args.json else sys.stdout, fps)
    recorder = Motion3Recorder(fps) if args.record is not None else None
    stop = threading.Event()
    previous = None
    if threading.current_thread() is threading.main_thread():
        # The first Ctrl-C ends the audio (the frames still due come back and --record is
        # written); a second one stops at once.
        def interrupt(signum, frame):
            if stop.is_set():
                raise KeyboardInterrupt
            stop.set()
        previous = signal.signal(signal.SIGINT, interrupt)
    if text is not None:
        _write_line(text.out, (
            f"koma live: {source.description}, {source.sample_rate} Hz, {source.channels} "
            f"channel{'' if source.channels == 1 else 's'}, {source.sample_format.upper()} -> "
            f"{args.server}{' (Ctrl-C ends)' if args.input is None else ''}"))
    vts_failure = None
    try:
        chunks = source.chunks(speed=1.0 if args.speed is None else args.speed,
                               seconds=args.seconds, stop=stop)
        with make_client(args) as client:
            for frame in client.live(chunks, source.sample_rate, source.channels,
                                     source.sample_format, **_settings(args)):
                if recorder is not None:
                    recorder.add(frame)
                if vmc is not None:
                    vmc.send(frame)
                if vts is not None and vts_failure is None:
                    try:
                        vts.send(frame)
                    except VtsError as error:
                        # As `koma live`: the audio ends; the frames still due come back to
                        # the other outputs; the error is reported when the stream has ended.
                        vts_failure = error
                        stop.set()
                shown = text.frame(frame) if text is not None else True
                if args.json:
                    line = json.dumps(frame.to_dict(), separators=(",", ":"))  # as `koma`'s
                    shown = _write_line(sys.stdout, line) and shown
                if not shown:
                    break  # the output's reader has gone (| head): stop the stream, quietly
    except BaseException as error:
        if recorder is not None and recorder.mouth:
            recorder.write(args.record)  # the frames that came before the error
        if isinstance(error, _live_sources.AudioSourceError):  # arecord or sox failed
            if args.input is not None:
                raise OSError(f"--input {args.input}: {error}") from None
            raise OSError(f"--device {source.device}: {error} (`arecord -L` lists the capture "
                          "devices; --input FILE plays a recording instead)") from None
        raise
    finally:
        source.close()
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
        vts_closed = vts.close() if vts is not None else None
    if recorder is not None:
        if not recorder.mouth:
            sys.stderr.write(f"koma: --record {args.record}: no frame was streamed: nothing "
                             "to write\n")
            return 1
        recorder.write(args.record)
    if text is not None:
        text.close()
    for failure in (vts_failure, vts_closed):  # as `koma live`: the sink's, then its Close's
        if failure is not None:
            sys.stderr.write(f"koma: {failure}\n")
            return 1
    return 0

"""`python3 -m koma live`: LipBlink from a live voice (the LiveLipBlink stream), as the C++
`koma live`: a file played at real time (--input) or the microphone (ALSA's arecord), the
frames as JSON lines (--json), VMC blend shapes (--vmc) and a motion3.json (--record).

    python3 -m koma live [--input FILE] [--device DEV] [--json] [--vmc [HOST:PORT]]
        [--seconds S] [--speed X] [--lookahead N] [--record OUT.motion3.json] ...
"""
import argparse
import json
import os
import signal
import sys
import threading

from koma import _live_sources
from koma._live_record import Motion3Recorder
from koma._vmc import VmcSender, parse_target

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
    p = commands.add_parser(
        "live", help="mouth flaps and blinks from a live voice (LiveLipBlink)",
        description="Streams a voice to the server and gets one frame per 24 fps grid frame "
                    "back as soon as it is decided: from a file played at real time "
                    "(--input), else the microphone through ALSA's arecord.")
    p.add_argument("--input", metavar="FILE",
                   help="a recording played at real time: WAV, or FLAC, Ogg, MP3 through sox "
                        "(default: the microphone)")
    p.add_argument("--device", default="default",
                   help="the microphone's ALSA device (arecord -D; default \"default\"; "
                        "\"null\" for no sound card)")
    p.add_argument("--json", action="store_true",
                   help="one JSON object per frame on stdout, as `koma live --json`")
    p.add_argument("--vmc", nargs="?", const="", metavar="HOST:PORT",
                   help="send VMC blend shapes A and Blink per frame over OSC (default "
                        "127.0.0.1:39539; needs python3-liblo)")
    p.add_argument("--record", metavar="OUT.motion3.json",
                   help="write the frames as a motion3.json (ParamMouthOpenY, ParamEyeLOpen, "
                        "ParamEyeROpen stepped on the grid)")
    p.add_argument("--seconds", type=_not_negative,
                   help="stop after this many seconds of audio (default: the whole file, or "
                        "until Ctrl-C)")
    p.add_argument("--speed", type=_not_negative,
                   help="--input: play at this many times real time (default 1; 0: as fast "
                        "as the server takes it)")
    p.add_argument("--lookahead", type=_lookahead, default=2,
                   help="grid frames the server waits past a frame before deciding it, 0-3 "
                        "(default 2; each 41.7 ms)")
    p.add_argument("--mode", choices=["random", "follow"],
                   help="mouth drawings: random (the paper, default) or follow the loudness")
    p.add_argument("--on", type=int, help="frames each mouth drawing is held (default 3)")
    p.add_argument("--seed", type=int, help="seed of the random mouth shapes and auto-blinks")
    p.add_argument("--auto-blink", type=float, metavar="MEAN_S",
                   help="blink every MEAN_S seconds on average")
    p.add_argument("--timing-fps", type=float, help="film grid in frames per second (default 24)")
    common(p, deadline=None)


def _source(args):
    if args.input is not None:
        return _live_sources.AudioFile(args.input)
    if args.speed is not None:
        raise _Usage("--speed: only with --input (the microphone is real time)")
    return _live_sources.Microphone(args.device, MIC_RATE, 1)


class _Usage(Exception):
    pass


def _summary(count, speech, blinks, late, fps):
    late = sorted(late)
    median = late[len(late) // 2] if late else 0.0
    return (f"koma live: {count} frames ({count / fps:.2f} s), speech in {speech}, "
            f"{blinks} blinks, decided {median:.1f} ms after a frame's end (median)\n")


def _write_line(text):
    """Writes and flushes a line to stdout; False when its reader has gone (then stdout points
    at /dev/null, so the interpreter's own flush at exit does not fail)."""
    try:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()
        return True
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return False


def run(args, make_client):
    """The subcommand; returns the exit status (KomaError and OSError reach main())."""
    try:
        vmc = VmcSender(*parse_target(args.vmc)) if args.vmc is not None else None
    except ValueError as error:
        sys.stderr.write(f"koma: {error}\n")
        return 2
    except ImportError as error:
        sys.stderr.write(f"koma: {error}\n")
        return 1
    try:
        source = _source(args)
    except _Usage as error:
        sys.stderr.write(f"koma: {error}\n")
        return 2
    fps = args.timing_fps or 24.0
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
    count = speech = blinks = 0
    late = []
    try:
        chunks = source.chunks(speed=1.0 if args.speed is None else args.speed,
                               seconds=args.seconds, stop=stop)
        auto = {"enabled": True, "mean_interval_s": args.auto_blink} \
            if args.auto_blink is not None else None
        mode = {"random": "MOUTH_RANDOM", "follow": "MOUTH_FOLLOW"}.get(args.mode)
        with make_client(args) as client:
            frames = client.live(
                chunks, source.sample_rate, source.channels, source.sample_format,
                lookahead=args.lookahead, seed=args.seed, timing_fps=args.timing_fps,
                mouth={"mode": mode, "frames_per_shape": args.on},
                eyes={"auto_blink": auto}, timeout=args.deadline)
            for frame in frames:
                count += 1
                speech += frame.speech
                blinks += frame.blink_start
                late.append(frame.late_ms)
                if args.json and not _write_line(json.dumps(frame.to_dict())):
                    break  # stdout closed (| head): stop the stream, quietly
                if vmc is not None:
                    vmc.send(frame)
                if recorder is not None:
                    recorder.add(frame)
    except BaseException:
        if recorder is not None and count:
            recorder.write(args.record)  # the frames that came before the error
        raise
    finally:
        source.close()
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    if recorder is not None:
        recorder.write(args.record)
    sys.stderr.write(_summary(count, speech, blinks, late, fps))
    return 0

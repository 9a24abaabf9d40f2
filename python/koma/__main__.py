"""`python3 -m koma`: the C++ `koma` CLI's subcommands for the three RPCs and health, through
the Python package (the file goes over the wire; the server parses and writes it).

    python3 -m koma skeletal IN.bvh -o OUT.bvh [--omit N] [--hold N] [--max-hold N] ...
    python3 -m koma curves IN.motion3.json|IN.csv -o OUT [--on N] [--keys 0,10,...] ...
    python3 -m koma curves SKELETON.json -o OUT.json [--animation NAME,...] [--on N] ...
    python3 -m koma lipblink IN.motion3.json|IN.csv -o OUT [--mouth ID,...] [--mode ...] ...
    python3 -m koma lipblink [IN] --audio VOICE.wav|--rhubarb CUES.json -o OUT ...
    python3 -m koma lipblink SKELETON.json --animation NAME --mouth-slot SLOT
        [--audio VOICE.wav|--rhubarb CUES|--speech B-E,...] [--eye-slot SLOT,...] -o OUT.json
    python3 -m koma health [--server HOST:PORT]
    python3 -m koma live [--input FILE] [--json] [--vmc [HOST:PORT]] [--vts [URL]]
        [--record OUT.motion3.json] [--seconds S] [--speed X] [--lookahead N] ...
        (koma/_live_cli.py)

The flags are the C++ `koma` CLI's, with its syntax (lists comma-separated, --speech as
BEGIN-END frame intervals), and write the same bytes. Exit status: 0 done, 1 the call failed
("koma: CODE: message" on stderr, as `koma`), 2 usage ("koma: message"). Not here: the C++
client's --timing sheets, reports and cues, and writing a CSV from a motion3.json input (the
output file has the input's format; a voice alone writes a CSV for -o NAME.csv).
"""
import argparse
import json
import math
import os
import sys

import koma
from koma import _live_cli, _presets
from koma import _format_table
from koma._client import _is_spine


def _positive(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text} must be > 0")
    return value


def _ids(text):
    return [part for part in text.split(",") if part]


def _keys(text):
    return [int(part) for part in text.split(",") if part]


def _names(flag):
    """A comma list of names, as the C++ CLI's string lists (an empty name is refused)."""
    def parse(text):
        names = text.split(",")
        if any(not name for name in names):
            raise argparse.ArgumentTypeError(f"{flag}: empty name in the list")
        return names
    return parse


def _intervals(flag):
    """BEGIN-END,... frame intervals (END one past the last frame), as the C++ CLI parses them."""
    def parse(text):
        intervals = []
        for item in text.split(","):
            begin, dash, end = item.partition("-")
            if not dash or not begin.isdigit() or not end.isdigit() or \
                    not begin.isascii() or not end.isascii():
                raise argparse.ArgumentTypeError(
                    f'{flag}: "{item}" is not a frame interval BEGIN-END (END one past the '
                    'last frame, e.g. 10-25)')
            if int(end) <= int(begin):
                raise argparse.ArgumentTypeError(
                    f'{flag}: "{item}": END must be greater than BEGIN')
            intervals.append((int(begin), int(end)))
        return intervals
    return parse


def _flatten(lists):
    """Repeated comma-list flags as one list, in order (None when not given)."""
    if lists is None:
        return None
    return [item for part in lists for item in part]


def _usage(message):
    sys.stderr.write(f"koma: {message}\n")
    raise SystemExit(2)


def _read_text(path):
    with open(path, "rb") as f:
        return f.read().decode("utf-8-sig", errors="replace")


def _is_csv_path(path):
    """*.csv, any case (the format table's CSV row, as `koma` tells a CSV by its name)."""
    return _format_table.format_from_name(path) == "csv"


def _is_spine_path(path):
    """A Spine skeleton JSON, told as koma tells it (formats/spine.h: first key "skeleton")."""
    if path is None or _is_csv_path(path):
        return False
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return False  # the call reports the unreadable file
    return _is_spine(data, None)


_BONE_TIMELINES = ("rotate", "translate", "translatex", "translatey", "scale", "scalex",
                   "scaley", "shear", "shearx", "sheary")


def _latest_key_time(value):
    """The latest "time" of any key below `value` (seconds), as koma's Spine reader finds an
    animation's length."""
    latest = 0.0
    if isinstance(value, list):
        for item in value:
            if isinstance(item, dict):
                time = item.get("time")
                if isinstance(time, (int, float)) and not isinstance(time, bool) and \
                        math.isfinite(time):
                    latest = max(latest, float(time))
            latest = max(latest, _latest_key_time(item))
    elif isinstance(value, dict):
        for member in value.values():
            latest = max(latest, _latest_key_time(member))
    return latest


def _spine_curve_ids(animation):
    """The curve ids koma reads from a Spine animation's bone timelines ("torso/rotate",
    "torso/translate.x", ...; formats/spine.h)."""
    ids = set()
    bones = animation.get("bones") if isinstance(animation, dict) else None
    for bone, timelines in (bones.items() if isinstance(bones, dict) else ()):
        for kind in (timelines if isinstance(timelines, dict) else ()):
            if kind == "rotate":
                ids.add(f"{bone}/rotate")
            elif kind in ("translate", "scale", "shear"):
                ids.update((f"{bone}/{kind}.x", f"{bone}/{kind}.y"))
            elif kind in _BONE_TIMELINES:
                ids.add(f"{bone}/{kind[:-1]}.{kind[-1]}")
    return ids


def _spine_animations_to_retime(path):
    """The skeleton's animations with bone keys over at least two frames, in file order: the
    ones `koma curves SKELETON` retimes when no --animation is given."""
    document = json.loads(_read_text(path))
    skeleton = document.get("skeleton")
    fps = skeleton.get("fps", 30) if isinstance(skeleton, dict) else 30
    animations = document.get("animations")
    names = []
    if not isinstance(animations, dict) or not isinstance(fps, (int, float)) or fps <= 0:
        return names
    for name, animation in animations.items():
        bones = animation.get("bones") if isinstance(animation, dict) else None
        if not isinstance(bones, dict):
            continue
        keyed = any(isinstance(timelines, dict) and any(
            kind in _BONE_TIMELINES and isinstance(keys, list) and keys
            for kind, keys in timelines.items()) for timelines in bones.values())
        if keyed and math.floor(_latest_key_time(animation) * fps + 0.5) >= 1:
            names.append(name)
    return names


def _common(parser, deadline=60.0):
    parser.add_argument("--server", default=os.environ.get("KOMA_SERVER", "127.0.0.1:50051"),
                        help="server host:port (default $KOMA_SERVER or 127.0.0.1:50051)")
    parser.add_argument("--deadline", type=_positive, default=deadline,
                        help=f"RPC deadline in seconds (default {deadline:g})"
                        if deadline is not None else "the stream's deadline in seconds "
                        "(default none)")
    parser.add_argument("--tls-ca", default=os.environ.get("KOMA_TLS_CA"),
                        help="PEM CA of the server's certificate: use TLS")
    parser.add_argument("--tls-cert", default=os.environ.get("KOMA_TLS_CERT"),
                        help="PEM client certificate (mutual TLS)")
    parser.add_argument("--tls-key", default=os.environ.get("KOMA_TLS_KEY"),
                        help="PEM key of --tls-cert")


def _io(parser, what):
    parser.add_argument("input", help=what)
    parser.add_argument("-o", "--output", required=True,
                        help="file to write (the input's format)")


def _parser():
    parser = argparse.ArgumentParser(
        prog="python3 -m koma",
        description="koma: retime animation into Japanese limited-animation timing")
    commands = parser.add_subparsers(dest="command", required=True)

    p = commands.add_parser("skeletal", help="retime a BVH mocap clip (RetimeSkeletal)")
    _io(p, "BVH file to retime")
    p.add_argument("--preset", choices=sorted(_presets.SKELETAL),
                   help="common settings, as koma --preset; paper: the paper's counts "
                        "instead of the anime defaults")
    p.add_argument("--omit", type=int, help="inbetween omissions Nio (with a count set: "
                                            "default 4)")
    p.add_argument("--hold", type=int, help="holds Nhf (with a count set: default frames / 3)")
    p.add_argument("--max-hold", type=int, help="longest run of one drawing (default 3)")
    p.add_argument("--omissions-per-second", type=float,
                   help="omission rate per second of the clip, instead of --omit (default 1 "
                        "unless a count is set)")
    p.add_argument("--drawings-per-second", type=float,
                   help="drawing rate: 12 on twos, 8 on threes (24 fps grid; default 8 "
                        "unless a count is set)")
    p.add_argument("--cut-neighbour-ratio", type=float,
                   help="cuts: isolated jump ratio to its neighbours (default 20; 0: no cuts)")
    p.add_argument("--cut-median-ratio", type=float,
                   help="cuts: jump ratio to the clip's median SSD (default 20)")
    p.add_argument("--no-keep-length", action="store_true",
                   help="do not re-insert duplicates after omissions")
    p.add_argument("--hold-first", action="store_true", help="run holds before omissions")
    p.add_argument("--root-relative", action="store_true",
                   help="measure motion relative to the root joint")
    p.add_argument("--timing-fps", type=float,
                   help="film grid in frames per second (default 24; 0: source frames)")
    p.add_argument("--output-rate", choices=["source", "timing"],
                   help="source (default: the BVH's rate and length) or timing (one frame "
                        "per grid frame)")
    p.add_argument("--timing-from", metavar="SHEET.xdts|TIMING.csv",
                   help="apply the timing of an edited XDTS sheet or --timing CSV instead of "
                        "computing one (cell N shows source frame N; a blank cell holds the "
                        "frame before)")
    _common(p)

    p = commands.add_parser("curves", help="koma-uchi on animation curves (RetimeCurves)")
    _io(p, "motion3.json, Spine skeleton JSON, or CSV (frame,<id>,... per frame)")
    p.add_argument("--animation", "--spine-animation", action="append",
                   type=_names("--animation"), metavar="NAME,...",
                   help="Spine skeleton: the animation to retime (repeatable or a comma list; "
                        "default every animation with bone keys)")
    p.add_argument("--on", type=int, help="frames per drawing: 2 on twos, 3 on threes "
                                          "(default 3)")
    p.add_argument("--keys", type=_keys, help="key pose frames, e.g. 0,10,25")
    p.add_argument("--tame", type=float, help="tame strength >= 1 (slow start)")
    p.add_argument("--tsume", type=float, help="tsume strength >= 1 (slow arrival)")
    p.add_argument("--curve-on", action="append", default=[],
                   help="ID=N: this curve on N (repeatable)")
    p.add_argument("--fps", type=float, help="frames per second of a CSV input (default 30)")
    p.add_argument("--timing-fps", type=float,
                   help="film grid in frames per second (default 24; 0: source frames)")
    p.add_argument("--timing-from", metavar="SHEET.xdts",
                   help="apply the timing of an edited XDTS (the sheet --xdts wrote) instead "
                        "of computing one; its cells are read against koma's answer for the "
                        "same input and flags (docs/usage.md)")
    _common(p)

    p = commands.add_parser("lipblink", help="mouth flaps and anime blinks (LipBlink)")
    p.add_argument("--timing-from", metavar="SHEET.xdts",
                   help="apply the timing of an edited XDTS (the sheet --xdts wrote) instead "
                        "of computing one; its cells are read against koma's answer for the "
                        "same input and flags (docs/usage.md)")
    p.add_argument("input", nargs="?",
                   help="motion3.json, Spine skeleton JSON, or CSV (frame,<id>,... per frame); "
                        "optional with --audio or --rhubarb (a new motion is written)")
    p.add_argument("-o", "--output", required=True,
                   help="file to write (the input's format; a voice alone: .csv or motion3.json)")
    p.add_argument("--audio", metavar="FILE",
                   help="a voice recording (WAV, FLAC, Ogg Vorbis/Opus, MP3): speech and mouth "
                        "drawings from it")
    p.add_argument("--rhubarb", metavar="FILE",
                   help="Rhubarb Lip Sync's mouth cues (JSON or TSV), in place of --audio")
    p.add_argument("--speech", "--mouth-speech", action="append", type=_intervals("--speech"),
                   metavar="BEGIN-END,...",
                   help="speech intervals in frames, END one past the last (repeatable)")
    p.add_argument("--animation", "--spine-animation", metavar="NAME",
                   help="Spine skeleton: the animation to key the mouth and eyes in (added "
                        "when missing)")
    p.add_argument("--mouth-slot", "--spine-mouth-slot", metavar="SLOT",
                   help="Spine skeleton: the mouth slot")
    p.add_argument("--mouth-attachments", "--spine-mouth-attachments",
                   type=_names("--mouth-attachments"), metavar="CLOSED,MID,OPEN",
                   help="its three attachments (default SLOT_closed,SLOT_mid,SLOT_open)")
    p.add_argument("--eye-slot", "--eye-slots", "--spine-eye-slots", action="append",
                   type=_names("--eye-slot"), metavar="SLOT,...",
                   help="Spine skeleton: the eye slots")
    p.add_argument("--eye-attachments", "--spine-eye-attachments",
                   type=_names("--eye-attachments"), metavar="OPEN,HALF,CLOSED",
                   help="their three attachments (default SLOT_open,SLOT_half,SLOT_closed)")
    p.add_argument("--mouth", type=_ids, help="mouth-open curve ids (default ParamMouthOpenY)")
    p.add_argument("--eyes", type=_ids,
                   help="eye-open curve ids (default ParamEyeLOpen,ParamEyeROpen)")
    p.add_argument("--mode", choices=["random", "follow"],
                   help="random (the paper) or follow the input (default random; with "
                        "--rhubarb the cues' own drawings)")
    p.add_argument("--seed", type=int, help="seed of the random mouth shapes and auto-blinks")
    p.add_argument("--auto-blink", type=float, metavar="MEAN_S",
                   help="insert blinks every MEAN_S seconds on average")
    p.add_argument("--on", type=int, help="frames each mouth drawing is held (default 3)")
    p.add_argument("--unlinked-eyes", action="store_true",
                   help="time each eye's blinks on its own")
    p.add_argument("--fps", type=float, help="frames per second of a CSV input (default 30)")
    p.add_argument("--timing-fps", type=float,
                   help="film grid in frames per second (default 24; 0: source frames)")
    _common(p)

    p = commands.add_parser("health", help="ask the server's grpc.health.v1 service")
    p.add_argument("--service", default="", help="service name (default: the whole server)")
    _common(p, deadline=5.0)

    _live_cli.add_parser(commands, _common)
    return parser


def _client(args):
    tls = False
    if args.tls_ca or args.tls_cert:
        tls = (args.tls_ca, args.tls_cert, args.tls_key)
    return koma.Client(args.server, timeout=args.deadline or koma._client.DEFAULT_TIMEOUT_S,
                       tls=tls)


def _curve_overrides(entries):
    overrides = []
    for entry in entries:
        curve_id, _, n = entry.rpartition("=")
        if not curve_id or not n.lstrip("-").isdigit():
            raise SystemExit(f"koma: --curve-on {entry}: expected ID=N, e.g. ParamHair=2")
        overrides.append({"curve_id": curve_id, "frames_per_drawing": int(n)})
    return overrides


def _check_output_format(args, spine=False):
    if spine:
        if _is_csv_path(args.output):
            _usage(f"-o {args.output}: a Spine skeleton is written back as Spine JSON "
                   "(-o OUT.json)")
        return
    if args.input is None:
        return  # a voice alone: -o NAME.csv writes a CSV, any other name a motion3.json
    if _is_csv_path(args.input) != _is_csv_path(args.output):
        _usage(f"-o {args.output}: python3 -m koma writes the input's format "
               "(.csv for a CSV input, motion3.json otherwise)")


_SPINE_LIPBLINK_FLAGS = "--animation, --mouth-slot, --eye-slot, --mouth-attachments, " \
    "--eye-attachments"


def _check_lip_blink(args, spine):
    """The C++ CLI's usage checks of `koma lipblink`, with its messages."""
    if args.audio is not None and args.rhubarb is not None:
        _usage("--audio and --rhubarb: give one voice, not both")
    voice = args.audio is not None or args.rhubarb is not None
    if args.input is None and not voice:
        _usage("IN is required (a motion3.json or CSV), or --audio FILE / --rhubarb FILE")
    spine_flags = args.animation is not None or args.mouth_slot is not None or \
        args.mouth_attachments is not None or args.eye_slot is not None or \
        args.eye_attachments is not None
    if spine_flags and args.input is None:
        _usage("--animation, --mouth-slot, --eye-slot: IN, a Spine skeleton JSON, is required")
    if spine_flags and not spine:
        _usage(f"{_SPINE_LIPBLINK_FLAGS}: {args.input} is not a Spine skeleton")
    if spine and not spine_flags:
        _usage(f"{args.input} is a Spine skeleton: `koma lipblink` reads Live2D motion3.json or "
               "per-frame CSV; key a skeleton's mouth and eyes with --animation NAME and "
               "--mouth-slot SLOT / --eye-slot SLOT; retime Spine animations with `koma curves`")


def _retime_spine(client, args, options):
    """`koma curves SKELETON`: one call per animation, each on the skeleton the previous call
    wrote (as the C++ CLI's --send-file does; its files are the same bytes either way)."""
    names = _flatten(args.animation)
    if names is None:
        names = _spine_animations_to_retime(args.input) or [None]  # none: the server says why
    names = list(dict.fromkeys(names))  # each once, in the order given
    # --curve-on ID=N: applied to the animations that have the curve; an id none has is a
    # typo (the C++ CLI's rule and message).
    overrides = options.pop("curve_overrides")
    animations = json.loads(_read_text(args.input)).get("animations") or {}
    ids = {name: _spine_curve_ids(animations.get(name)) for name in names if name is not None}
    for override in overrides:
        if names != [None] and not any(override["curve_id"] in i for i in ids.values()):
            _usage(f'--curve-on: no animation retimed here has the curve "{override["curve_id"]}" '
                   "(ids are BONE/rotate, BONE/translate.x, BONE/scale.y, BONE/shear.x, ...)")
    source, result, counts = args.input, None, {"curves": 0, "drawings": 0}
    for name in names:
        own = [o for o in overrides if name is None or o["curve_id"] in ids[name]]
        result = client.retime_curves(source, format="spine", animation=name,
                                      curve_overrides=own, **options)
        counts["curves"] += result.counts["curves"]
        counts["drawings"] += result.counts["drawings"]
        source = result.output
    return names, result, counts


def _run(args):
    if args.command == "live":
        return _live_cli.run(args, _client)
    if args.command == "health":
        with _client(args) as client:
            status = client.health(args.service)
        print(status)
        return 0 if status == "SERVING" else 1
    with _client(args) as client:
        if args.command == "skeletal":
            result = client.retime_skeletal(
                args.input, preset=args.preset, omissions=args.omit, holds=args.hold, max_hold=args.max_hold,
                keep_length=not args.no_keep_length,
                order="HOLD_THEN_OMIT" if args.hold_first else "OMIT_THEN_HOLD",
                root_relative=args.root_relative, timing_fps=args.timing_fps,
                output_rate="TIMING_RATE" if args.output_rate == "timing" else None,
                omissions_per_second=args.omissions_per_second,
                drawings_per_second=args.drawings_per_second,
                cut_neighbour_ratio=args.cut_neighbour_ratio,
                cut_median_ratio=args.cut_median_ratio, timing_from=args.timing_from)
            for warning in result.warnings:
                sys.stderr.write(f"koma: warning: {warning}\n")
            result.write(args.output)
            c = result.counts
            print(f"{args.input} -> {args.output} ({c['frames']} frames): omitted "
                  f"{c['omissions_applied']}, duplicated {c['duplicates_applied']}, held "
                  f"{c['holds_applied']}; source frames gone: {result.deleted_frames}")
        elif args.command == "curves":
            spine = _is_spine_path(args.input)
            if args.animation is not None and not spine:
                _usage(f"--animation: {args.input} is not a Spine skeleton")
            _check_output_format(args, spine)
            options = dict(key_frames=args.keys, frames_per_drawing=args.on, tame=args.tame,
                           tsume=args.tsume, curve_overrides=_curve_overrides(args.curve_on),
                           timing_fps=args.timing_fps)
            if spine:
                if args.fps is not None:
                    _usage("--fps: only for a CSV input (a skeleton's rate is skeleton.fps)")
                names, result, counts = _retime_spine(client, args, options)
                result.write(args.output)
                print(f"{args.input} -> {args.output}: animations "
                      f"{', '.join(n for n in names if n) or '(the only one)'}: "
                      f"{counts['curves']} curves, {counts['drawings']} drawings")
                return 0
            if args.timing_from is not None:
                options["timing_from"] = args.timing_from
            result = client.retime_curves(
                args.input, csv_fps=args.fps if _is_csv_path(args.input) else None,
                **options)
            result.write(args.output)
            print(f"{args.input} -> {args.output}: {result.counts['curves']} curves, key poses "
                  f"{result.key_frames}, {result.counts['drawings']} drawings")
        else:
            spine = _is_spine_path(args.input)
            _check_lip_blink(args, spine)
            _check_output_format(args, spine)
            auto = {"enabled": True, "mean_interval_s": args.auto_blink} \
                if args.auto_blink is not None else None
            # As the C++ CLI: random unless --mode follow; with Rhubarb cues and no --mode,
            # unset (the server follows the cues' drawings).
            mode = "MOUTH_FOLLOW" if args.mode == "follow" else \
                "MOUTH_RANDOM" if args.mode == "random" or args.rhubarb is None else None
            csv_input = args.input is not None and _is_csv_path(args.input)
            options = {}
            if spine:
                options = dict(animation=args.animation, mouth_slot=args.mouth_slot,
                               mouth_attachments=args.mouth_attachments,
                               eye_slots=_flatten(args.eye_slot),
                               eye_attachments=args.eye_attachments)
            elif args.input is None:
                # A new motion: at --fps (default 30), the format -o names, as the C++ CLI.
                options = dict(voice_motion_fps=args.fps if args.fps is not None else 30.0,
                               voice_output="VOICE_OUTPUT_CSV"
                               if _is_csv_path(args.output)
                               else "VOICE_OUTPUT_MOTION3_JSON")
            if args.timing_from is not None:
                if spine or args.audio is not None or args.rhubarb is not None:
                    _usage("--timing-from: not with a voice (--audio, --rhubarb) or a Spine "
                           "skeleton")
                options["timing_from"] = args.timing_from
            result = client.lip_blink(
                args.input, csv_fps=args.fps if csv_input else None,
                audio=args.audio, rhubarb_cues=args.rhubarb,
                mouth={"ids": None if spine else args.mouth, "frames_per_shape": args.on,
                       "mode": mode, "speech": _flatten(args.speech)},
                eyes={"ids": None if spine else args.eyes,
                      "linked": False if args.unlinked_eyes else None, "auto_blink": auto},
                seed=args.seed, timing_fps=args.timing_fps, **options)
            result.write(args.output)
            source = args.input if args.input is not None else (args.audio or args.rhubarb)
            print(f"{source} -> {args.output} (seed {result.seed}): "
                  f"{result.counts['mouth_holds']} mouth holds, {result.counts['blinks']} blinks")
    return 0


def main(argv=None):
    args = _parser().parse_args(argv)
    try:
        return _run(args)
    except koma.KomaError as error:
        sys.stderr.write(f"koma: {error.code.name}: {error.message}\n")
        return 1
    except koma.SheetError as error:  # --timing-from: as the C++ client words it
        sys.stderr.write(f"koma: {error}\n")
        return 1
    except OSError as error:
        sys.stderr.write(f"koma: {error}\n")
        return 1


if __name__ == "__main__":
    sys.exit(main())

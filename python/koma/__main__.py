"""`python3 -m koma`: the C++ `koma` CLI's subcommands for the three RPCs and health, through
the Python package (the file goes over the wire; the server parses and writes it).

    python3 -m koma skeletal IN.bvh -o OUT.bvh [--omit N] [--hold N] [--max-hold N] ...
    python3 -m koma curves IN.motion3.json|IN.csv -o OUT [--on N] [--keys 0,10,...] ...
    python3 -m koma lipblink IN.motion3.json|IN.csv -o OUT [--mouth ID,...] [--mode ...] ...
    python3 -m koma health [--server HOST:PORT]

Exit status: 0 done, 1 the call failed ("koma: CODE: message" on stderr, as `koma`), 2 usage.
Not here: the C++ client's --timing sheets and writing a CSV from a motion3.json input (the
output file has the input's format).
"""
import argparse
import os
import sys

import koma


def _positive(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"{text} must be > 0")
    return value


def _ids(text):
    return [part for part in text.split(",") if part]


def _keys(text):
    return [int(part) for part in text.split(",") if part]


def _common(parser, deadline=60.0):
    parser.add_argument("--server", default=os.environ.get("KOMA_SERVER", "127.0.0.1:50051"),
                        help="server host:port (default $KOMA_SERVER or 127.0.0.1:50051)")
    parser.add_argument("--deadline", type=_positive, default=deadline,
                        help=f"RPC deadline in seconds (default {deadline:g})")
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
    p.add_argument("--omit", type=int, help="inbetween omissions Nio (default 4)")
    p.add_argument("--hold", type=int, help="holds Nhf (default frames / 3)")
    p.add_argument("--max-hold", type=int, help="longest run of one drawing (default 3)")
    p.add_argument("--omissions-per-second", type=float,
                   help="omission rate per second of the clip, instead of --omit")
    p.add_argument("--drawings-per-second", type=float,
                   help="drawing rate: 12 on twos, 8 on threes (24 fps grid)")
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
    _common(p)

    p = commands.add_parser("curves", help="koma-uchi on animation curves (RetimeCurves)")
    _io(p, "motion3.json, or CSV (frame,<id>,... per frame)")
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
    _common(p)

    p = commands.add_parser("lipblink", help="mouth flaps and anime blinks (LipBlink)")
    _io(p, "motion3.json, or CSV (frame,<id>,... per frame)")
    p.add_argument("--mouth", type=_ids, help="mouth-open curve ids (default ParamMouthOpenY)")
    p.add_argument("--eyes", type=_ids,
                   help="eye-open curve ids (default ParamEyeLOpen,ParamEyeROpen)")
    p.add_argument("--mode", choices=["random", "follow"], default="random",
                   help="random (the paper) or follow the input (default random)")
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
    return parser


def _client(args):
    tls = False
    if args.tls_ca or args.tls_cert:
        tls = (args.tls_ca, args.tls_cert, args.tls_key)
    return koma.Client(args.server, timeout=args.deadline, tls=tls)


def _curve_overrides(entries):
    overrides = []
    for entry in entries:
        curve_id, _, n = entry.rpartition("=")
        if not curve_id or not n.lstrip("-").isdigit():
            raise SystemExit(f"koma: --curve-on {entry}: expected ID=N, e.g. ParamHair=2")
        overrides.append({"curve_id": curve_id, "frames_per_drawing": int(n)})
    return overrides


def _check_output_format(args):
    if args.input.lower().endswith(".csv") != args.output.lower().endswith(".csv"):
        sys.stderr.write(f"koma: -o {args.output}: python3 -m koma writes the input's format "
                         "(.csv for a CSV input, motion3.json otherwise)\n")
        raise SystemExit(2)


def _run(args):
    if args.command == "health":
        with _client(args) as client:
            status = client.health(args.service)
        print(status)
        return 0 if status == "SERVING" else 1
    with _client(args) as client:
        if args.command == "skeletal":
            result = client.retime_skeletal(
                args.input, omissions=args.omit, holds=args.hold, max_hold=args.max_hold,
                keep_length=not args.no_keep_length,
                order="HOLD_THEN_OMIT" if args.hold_first else "OMIT_THEN_HOLD",
                root_relative=args.root_relative, timing_fps=args.timing_fps,
                output_rate="TIMING_RATE" if args.output_rate == "timing" else None,
                omissions_per_second=args.omissions_per_second,
                drawings_per_second=args.drawings_per_second,
                cut_neighbour_ratio=args.cut_neighbour_ratio,
                cut_median_ratio=args.cut_median_ratio)
            result.write(args.output)
            c = result.counts
            print(f"{args.input} -> {args.output} ({c['frames']} frames): omitted "
                  f"{c['omissions_applied']}, duplicated {c['duplicates_applied']}, held "
                  f"{c['holds_applied']}; source frames gone: {result.deleted_frames}")
        elif args.command == "curves":
            _check_output_format(args)
            result = client.retime_curves(
                args.input, csv_fps=args.fps if args.input.lower().endswith(".csv") else None,
                key_frames=args.keys, frames_per_drawing=args.on, tame=args.tame,
                tsume=args.tsume, curve_overrides=_curve_overrides(args.curve_on),
                timing_fps=args.timing_fps)
            result.write(args.output)
            print(f"{args.input} -> {args.output}: {result.counts['curves']} curves, key poses "
                  f"{result.key_frames}, {result.counts['drawings']} drawings")
        else:
            _check_output_format(args)
            auto = {"enabled": True, "mean_interval_s": args.auto_blink} \
                if args.auto_blink is not None else None
            result = client.lip_blink(
                args.input, csv_fps=args.fps if args.input.lower().endswith(".csv") else None,
                mouth={"ids": args.mouth, "frames_per_shape": args.on,
                       "mode": "MOUTH_FOLLOW" if args.mode == "follow" else "MOUTH_RANDOM"},
                eyes={"ids": args.eyes, "linked": False if args.unlinked_eyes else None,
                      "auto_blink": auto},
                seed=args.seed, timing_fps=args.timing_fps)
            result.write(args.output)
            print(f"{args.input} -> {args.output} (seed {result.seed}): "
                  f"{result.counts['mouth_holds']} mouth holds, {result.counts['blinks']} blinks")
    return 0


def main(argv=None):
    args = _parser().parse_args(argv)
    try:
        return _run(args)
    except koma.KomaError as error:
        sys.stderr.write(f"koma: {error.code.name}: {error.message}\n")
        return 1
    except OSError as error:
        sys.stderr.write(f"koma: {error}\n")
        return 1


if __name__ == "__main__":
    sys.exit(main())

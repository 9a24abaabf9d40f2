"""The same request through the Python package (a file-carrying request: the server parses and
writes the file) and through the C++ `koma` CLI (it parses and writes locally, and sends the
decoded motion) gives byte-identical files, for every sample and real mocap file."""
import json
import pathlib

import pytest

from conftest import run_cli, run_python_cli, source_path

BVH_FILES = [source_path("samples", "pitch.bvh"), source_path("samples", "mocap_120fps.bvh")] + \
    [source_path("tests", "testdata", name) for name in
     ("bvh_test1.bvh", "bvh_test2.bvh", "bvh_test3.bvh")]
# 2- and 3-frame edge cases (CRLF, unusual channels): too short for a film grid or omissions.
SMALL_BVH_FILES = [source_path("tests", "testdata", name) for name in
                   ("two_joints_crlf.bvh", "unusual_channels.bvh")]

# (CLI flags, the same as Python options)
SKELETAL_OPTIONS = [
    ([], {}),
    (["--timing-fps", "0", "--omit", "2", "--hold", "5"],
     {"timing_fps": 0, "omissions": 2, "holds": 5}),
    (["--output-rate", "timing", "--max-hold", "2"], {"output_rate": "TIMING_RATE", "max_hold": 2}),
    (["--timing-fps", "0", "--hold-first", "--root-relative", "--no-keep-length"],
     {"timing_fps": 0, "order": "HOLD_THEN_OMIT", "root_relative": True, "keep_length": False}),
]


@pytest.mark.parametrize("path", BVH_FILES, ids=lambda p: pathlib.Path(p).name)
@pytest.mark.parametrize("flags,options", SKELETAL_OPTIONS, ids=["default", "no-grid", "timing-rate",
                                                                 "hold-first"])
def test_skeletal_output_equals_the_cli(server, client, tmp_path, path, flags, options):
    expected = tmp_path / "cli.bvh"
    run_cli("skeletal", path, "-o", str(expected), "--server", server.address, *flags)
    result = client.retime_skeletal(path, **options)
    assert result.output_bytes == expected.read_bytes()
    # The timing map agrees with the file: as many output frames as the BVH has.
    frames_line = next(l for l in result.output.splitlines() if l.startswith("Frames:"))
    assert int(frames_line.split()[1]) == len(result.source_frames) == result.counts["frames"]
    assert result.timing == dict(enumerate(result.source_frames))


@pytest.mark.parametrize("path", SMALL_BVH_FILES, ids=lambda p: pathlib.Path(p).name)
def test_small_skeletal_output_equals_the_cli(server, client, tmp_path, path):
    expected = tmp_path / "cli.bvh"
    run_cli("skeletal", path, "-o", str(expected), "--server", server.address, "--timing-fps", "0")
    assert client.retime_skeletal(path, timing_fps=0).output_bytes == expected.read_bytes()


CURVE_FILES = [source_path("samples", "arm_head.motion3.json"),
               source_path("samples", "talk_blink.motion3.json"),
               source_path("tests", "testdata", "small.motion3.json"),
               source_path("tests", "testdata", "curves_crlf.csv")]

CURVES_OPTIONS = [
    ([], {}),
    (["--on", "2", "--timing-fps", "0"], {"frames_per_drawing": 2, "timing_fps": 0}),
    (["--tame", "1.5", "--tsume", "1.25", "--keys", "0,2"],
     {"tame": 1.5, "tsume": 1.25, "key_frames": [0, 2]}),
]


@pytest.mark.parametrize("path,curve", [
    (source_path("samples", "arm_head.motion3.json"), "ParamAngleX"),
    (source_path("tests", "testdata", "curves_crlf.csv"), "ParamEyeLOpen"),
], ids=["motion3", "csv"])
def test_curve_overrides_equal_the_cli(server, client, tmp_path, path, curve):
    expected = tmp_path / ("cli" + _suffix(path))
    run_cli("curves", path, "-o", str(expected), "--server", server.address, "--on", "3",
            "--curve-on", f"{curve}=2", "--timing-fps", "0")
    result = client.retime_curves(path, frames_per_drawing=3, timing_fps=0,
                                  curve_overrides=[{"curve_id": curve, "frames_per_drawing": 2}])
    assert result.output_bytes == expected.read_bytes()
    # The curve's own n gets a timing of its own (in its timing group, with Live2D's groups).
    own = result.timings[result.curves[curve]["timing"]]
    assert own["frames_per_drawing"] == 2 and result.curves[curve]["timing"] != 0


def _suffix(path):
    return ".csv" if path.endswith(".csv") else ".motion3.json"


@pytest.mark.parametrize("path", CURVE_FILES, ids=lambda p: pathlib.Path(p).name)
@pytest.mark.parametrize("flags,options", CURVES_OPTIONS, ids=["default", "twos", "tame-tsume"])
def test_curves_output_equals_the_cli(server, client, tmp_path, path, flags, options):
    expected = tmp_path / ("cli" + _suffix(path))
    run_cli("curves", path, "-o", str(expected), "--server", server.address, *flags)
    result = client.retime_curves(path, **options)
    assert result.output_bytes == expected.read_bytes()
    assert result.key_frames[0] == 0
    assert result.counts["curves"] == len(result.curves) > 0


LIPBLINK_OPTIONS = [
    ([], {}),
    (["--seed", "7", "--mode", "follow"], {"seed": 7, "mouth": {"mode": "MOUTH_FOLLOW"}}),
    (["--timing-fps", "0", "--auto-blink", "1", "--unlinked-eyes", "--on", "2"],
     {"timing_fps": 0, "eyes": {"auto_blink": {"enabled": True, "mean_interval_s": 1.0},
                                "linked": False},
      "mouth": {"frames_per_shape": 2}}),
]


@pytest.mark.parametrize("flags,options", LIPBLINK_OPTIONS, ids=["default", "follow", "auto-blink"])
def test_lip_blink_output_equals_the_cli(server, client, tmp_path, flags, options):
    path = source_path("samples", "talk_blink.motion3.json")
    expected = tmp_path / "cli.motion3.json"
    run_cli("lipblink", path, "-o", str(expected), "--server", server.address, *flags)
    result = client.lip_blink(path, **options)
    assert result.output_bytes == expected.read_bytes()
    assert result.counts["mouth_holds"] > 0 and result.counts["eye_curves"] == 2


def test_lip_blink_csv_output_equals_the_cli(server, client, tmp_path):
    # talk_blink as CSV, written by the CLI itself (no retiming: --on 1 on ones, no grid).
    csv = tmp_path / "talk.csv"
    run_cli("curves", source_path("samples", "talk_blink.motion3.json"), "-o", str(csv),
            "--on", "1", "--timing-fps", "0", "--server", server.address)
    expected = tmp_path / "cli.csv"
    run_cli("lipblink", str(csv), "-o", str(expected), "--fps", "25", "--server", server.address)
    result = client.lip_blink(str(csv), csv_fps=25)
    assert result.output_bytes == expected.read_bytes()


@pytest.mark.parametrize("command,path,flags", [
    ("skeletal", source_path("samples", "pitch.bvh"), ["--omit", "3"]),
    ("skeletal", source_path("tests", "testdata", "bvh_test3.bvh"), ["--output-rate", "timing"]),
    ("curves", source_path("samples", "arm_head.motion3.json"), ["--on", "2"]),
    ("curves", source_path("tests", "testdata", "curves_crlf.csv"), ["--fps", "24"]),
    ("lipblink", source_path("samples", "talk_blink.motion3.json"), ["--seed", "3"]),
], ids=["skeletal", "skeletal-timing-rate", "curves", "curves-csv", "lipblink"])
def test_python_m_koma_writes_what_the_cli_writes(server, tmp_path, command, path, flags):
    suffix = ".bvh" if command == "skeletal" else _suffix(path)
    expected, got = tmp_path / ("cli" + suffix), tmp_path / ("py" + suffix)
    run_cli(command, path, "-o", str(expected), "--server", server.address, *flags)
    done = run_python_cli(command, path, "-o", str(got), "--server", server.address, *flags)
    assert done.returncode == 0, done.stderr
    assert got.read_bytes() == expected.read_bytes()


SPINE_FILES = [("matt-3.7.json", "shake_head"), ("hero-3.8.json", "walk"),
               ("hero-4.1.json", "idle"), ("hero-4.2.json", None)]


@pytest.mark.parametrize("name,animation", SPINE_FILES, ids=[n for n, _ in SPINE_FILES])
@pytest.mark.parametrize("flags,options", CURVES_OPTIONS[:2], ids=["default", "twos"])
def test_spine_output_equals_the_cli(server, client, tmp_path, name, animation, flags, options):
    path = source_path("tests", "testdata", "spine", name)
    expected = tmp_path / "cli.json"
    named = ["--animation", animation] if animation else []
    run_cli("curves", path, "-o", str(expected), "--server", server.address, *named, *flags)
    result = client.retime_curves(path, animation=animation, **options)
    assert result.output_bytes == expected.read_bytes()
    assert result.response.WhichOneof("output") == "spine_json"
    assert all("/" in curve_id for curve_id in result.curves)  # "bone/rotate", ...


def test_spine_errors_name_the_field(client):
    import koma
    path = source_path("tests", "testdata", "spine", "hero-3.8.json")
    with pytest.raises(koma.KomaError) as error:
        client.retime_curves(path)  # two animations with bone keys: name one
    assert "spine_animation: name the animation to retime" in str(error.value)
    # LipBlink into Spine: the server names the field (LipBlinkRequest.spine).
    with pytest.raises(koma.KomaError) as error:
        client.lip_blink(path, eye_slots=["eyes"])
    assert "spine.animation: the Spine animation to write the mouth and eyes into" in str(error.value)
    with pytest.raises(koma.KomaError) as error:
        client.lip_blink(path, animation="walk", mouth_slot="nose", mouth={"speech": [(3, 9)]})
    assert 'spine.mouth_slot no slot named "nose" (the skeleton has' in str(error.value)
    with pytest.raises(ValueError, match="only with a Spine skeleton"):
        client.lip_blink(audio=source_path("samples", "voice.flac"), mouth_slot="mouth")


# LipBlink into a Spine skeleton: the written skeleton is the CLI's, byte for byte.
SPINE_LIP_BLINK = [
    ("samples/hero.json",
     ["--animation", "talk", "--audio", "samples/voice.flac", "--mouth-slot", "mouth",
      "--eye-slot", "eyes", "--auto-blink", "1.5"],
     dict(animation="talk", audio="samples/voice.flac", mouth_slot="mouth", eye_slots=["eyes"],
          eyes={"auto_blink": {"enabled": True, "mean_interval_s": 1.5}})),
    ("tests/testdata/spine/hero-4.1.json",
     ["--animation", "walk", "--speech", "3-20", "--mouth-slot", "mouth", "--eye-slot", "eyes",
      "--eye-attachments", "eyes_open,eyes_half,eyes_closed"],
     dict(animation="walk", mouth={"speech": [(3, 20)]}, mouth_slot="mouth", eye_slots="eyes",
          eye_attachments=["eyes_open", "eyes_half", "eyes_closed"])),
    ("tests/testdata/spine/matt-3.7.json",
     ["--animation", "shake_head", "--speech", "2-30", "--mouth-slot", "mouth",
      "--mouth-attachments", "mouth_a,mouth_c,mouth_d", "--timing-fps", "0"],
     dict(animation="shake_head", mouth={"speech": [(2, 30)]}, mouth_slot="mouth",
          mouth_attachments=["mouth_a", "mouth_c", "mouth_d"], timing_fps=0)),
]


@pytest.mark.parametrize("name,flags,options", SPINE_LIP_BLINK,
                         ids=["hero-voice", "hero-4.1-speech", "matt-3.7"])
def test_spine_lip_blink_equals_the_cli(server, client, tmp_path, name, flags, options):
    path = source_path(*name.split("/"))
    flags = [source_path(*f.split("/")) if f.startswith("samples/") else f for f in flags]
    if "audio" in options:
        options = dict(options, audio=source_path(*options["audio"].split("/")))
    expected = tmp_path / "cli.json"
    run_cli("lipblink", path, "-o", str(expected), "--server", server.address, *flags)
    result = client.lip_blink(path, **options)
    assert result.response.WhichOneof("output") == "spine_json"
    assert result.output_bytes == expected.read_bytes()
    written = json.loads(result.output)
    animation = options["animation"]
    assert written["animations"][animation]["slots"]["mouth"]["attachment"]


# `python3 -m koma` with the Spine and voice flags of the C++ CLI: the same files, byte for
# byte. (subcommand, input or None, flags, ...) with "samples/..." and "spine/..." paths.
PYTHON_M_SPINE_AND_VOICE = [
    ("curves", "spine/hero-3.8.json", ["--animation", "walk"]),
    # Every animation with bone keys (one call each, chained), and a comma list.
    ("curves", "spine/hero-4.1.json", ["--on", "2"]),
    ("curves", "spine/hero-4.1.json", ["--animation", "walk,idle", "--tame", "1.5"]),
    ("curves", "spine/hero-4.1.json", ["--animation", "idle", "--animation", "walk"]),
    # --curve-on applied to the animations that have the curve (walk only here).
    ("curves", "spine/hero-4.1.json", ["--curve-on", "torso/rotate=2", "--curve-on",
                                       "head/rotate=1"]),
    ("lipblink", "samples/hero.json",
     ["--animation", "talk", "--audio", "samples/voice.flac", "--mouth-slot", "mouth",
      "--eye-slot", "eyes", "--auto-blink", "1.5", "--seed", "5"]),
    ("lipblink", "spine/hero-4.1.json",
     ["--animation", "walk", "--speech", "3-20,25-30", "--mouth-slot", "mouth",
      "--eye-slot", "eyes", "--eye-attachments", "eyes_open,eyes_half,eyes_closed"]),
    ("lipblink", "spine/matt-3.7.json",
     ["--animation", "shake_head", "--speech", "2-30", "--mouth-slot", "mouth",
      "--mouth-attachments", "mouth_a,mouth_c,mouth_d", "--timing-fps", "0"]),
    ("lipblink", "samples/talk_blink.motion3.json",
     ["--audio", "samples/voice.flac", "--seed", "2"]),
    ("lipblink", "samples/arm_head.motion3.json",
     ["--audio", "samples/voice.flac", "--mode", "follow", "--auto-blink", "2"]),
    ("lipblink", None, ["--audio", "samples/voice.flac"]),
    ("lipblink", None, ["--audio", "samples/voice.flac", "--fps", "24", "--csv"]),
]


def _sample_or_spine(path):
    if path.startswith("spine/"):
        return source_path("tests", "testdata", "spine", path[len("spine/"):])
    if path.startswith("samples/"):
        return source_path(*path.split("/"))
    return path


@pytest.mark.parametrize("command,name,flags", PYTHON_M_SPINE_AND_VOICE,
                         ids=["curves-3.8-walk", "curves-4.1-all", "curves-4.1-list",
                              "curves-4.1-repeated", "curves-4.1-curve-on",
                              "lipblink-spine-audio",
                              "lipblink-spine-speech", "lipblink-3.7", "lipblink-motion3-audio",
                              "lipblink-follow-audio", "lipblink-voice-alone",
                              "lipblink-voice-alone-csv"])
def test_python_m_koma_spine_and_voice_write_what_the_cli_writes(server, tmp_path, command,
                                                                 name, flags):
    flags = [_sample_or_spine(f) for f in flags]
    suffix = ".json" if name is None or not name.endswith(".motion3.json") else ".motion3.json"
    if "--csv" in flags:  # a voice alone written as CSV: the output's name says so
        flags.remove("--csv")
        suffix = ".csv"
    elif name is None:
        suffix = ".motion3.json"
    inputs = [] if name is None else [_sample_or_spine(name)]
    expected, got = tmp_path / ("cli" + suffix), tmp_path / ("py" + suffix)
    run_cli(command, *inputs, "-o", str(expected), "--server", server.address, *flags)
    done = run_python_cli(command, *inputs, "-o", str(got), "--server", server.address, *flags)
    assert done.returncode == 0, done.stderr
    assert got.read_bytes() == expected.read_bytes()
    if name is not None and "spine" in name or name == "samples/hero.json":
        written = json.loads(got.read_text())
        assert written["skeleton"] == json.loads(expected.read_text())["skeleton"]


def test_python_m_koma_curves_every_animation_differs_from_one(server, tmp_path):
    """Without --animation every animation with bone keys is retimed (the C++ CLI's rule), so
    the file differs from retiming walk alone; both equal the C++ CLI's."""
    path = source_path("tests", "testdata", "spine", "hero-4.1.json")
    every, walk = tmp_path / "every.json", tmp_path / "walk.json"
    for out, flags in ((every, []), (walk, ["--animation", "walk"])):
        done = run_python_cli("curves", path, "-o", str(out), "--server", server.address, *flags)
        assert done.returncode == 0, done.stderr
    assert every.read_bytes() != walk.read_bytes()
    before = json.loads(pathlib.Path(path).read_text())["animations"]
    after_every = json.loads(every.read_text())["animations"]
    after_walk = json.loads(walk.read_text())["animations"]
    changed_every = [n for n in before if before[n] != after_every[n]]
    changed_walk = [n for n in before if before[n] != after_walk[n]]
    assert changed_walk == ["walk"] and len(changed_every) >= 2 and "walk" in changed_every


PYTHON_M_USAGE_ERRORS = [
    (["lipblink", "-o", "x.json"],
     "IN is required (a motion3.json or CSV), or --audio FILE / --rhubarb FILE"),
    (["lipblink", "--audio", "samples/voice.flac", "--rhubarb", "r.json", "-o", "x.json"],
     "--audio and --rhubarb: give one voice, not both"),
    (["lipblink", "samples/talk_blink.motion3.json", "--animation", "talk", "-o", "x.json"],
     "--animation, --mouth-slot, --eye-slot, --mouth-attachments, --eye-attachments: "),
    (["lipblink", "--audio", "samples/voice.flac", "--mouth-slot", "mouth", "-o", "x.json"],
     "--animation, --mouth-slot, --eye-slot: IN, a Spine skeleton JSON, is required"),
    (["lipblink", "samples/hero.json", "--audio", "samples/voice.flac", "-o", "x.json"],
     "is a Spine skeleton: `koma lipblink` reads Live2D motion3.json or per-frame CSV"),
    (["lipblink", "samples/hero.json", "--animation", "talk", "--speech", "3-x", "-o", "x.json"],
     '--speech: "3-x" is not a frame interval BEGIN-END'),
    (["lipblink", "samples/hero.json", "--animation", "talk", "--speech", "9-3", "-o", "x.json"],
     '--speech: "9-3": END must be greater than BEGIN'),
    (["lipblink", "samples/hero.json", "--animation", "talk", "--mouth-attachments", "a,,c",
      "-o", "x.json"], "--mouth-attachments: empty name in the list"),
    (["lipblink", "samples/hero.json", "--animation", "talk", "--mouth-slot", "mouth",
      "--speech", "3-9", "-o", "x.csv"], "a Spine skeleton is written back as Spine JSON"),
    (["curves", "samples/hero.json", "--animation", "walk", "-o", "x.csv"],
     "a Spine skeleton is written back as Spine JSON"),
    (["curves", "samples/arm_head.motion3.json", "--animation", "walk", "-o", "x.motion3.json"],
     "--animation: "),
    (["curves", "samples/hero.json", "--animation", "walk,", "-o", "x.json"],
     "--animation: empty name in the list"),
    (["curves", "samples/hero.json", "--curve-on", "tail/rotate=2", "-o", "x.json"],
     '--curve-on: no animation retimed here has the curve "tail/rotate"'),
]


@pytest.mark.parametrize("args,message", PYTHON_M_USAGE_ERRORS,
                         ids=[f"error{i}" for i in range(len(PYTHON_M_USAGE_ERRORS))])
def test_python_m_koma_usage_errors_exit_2(server, tmp_path, args, message):
    args = [_sample_or_spine(a) for a in args]
    args = [str(tmp_path / a) if a.startswith("x.") else a for a in args]
    done = run_python_cli(*args, "--server", server.address)
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert message in done.stderr, done.stderr
    assert not any(tmp_path.iterdir())  # nothing written


def test_python_m_koma_spine_call_errors_exit_1(server, tmp_path):
    """An error the server finds (a slot the skeleton lacks) exits 1 with its code and field."""
    done = run_python_cli("lipblink", source_path("samples", "hero.json"), "--animation", "talk",
                          "--mouth-slot", "nose", "--speech", "3-9", "-o",
                          str(tmp_path / "x.json"), "--server", server.address)
    assert done.returncode == 1, done.stderr
    assert 'INVALID_ARGUMENT: spine.mouth_slot no slot named "nose"' in done.stderr


@pytest.mark.parametrize("cues_name", ["cues.json", "cues.tsv"])
@pytest.mark.parametrize("name,flags", [
    ("samples/hero.json", ["--animation", "talk", "--mouth-slot", "mouth", "--eye-slot", "eyes"]),
    ("samples/talk_blink.motion3.json", ["--seed", "3"]),
    (None, []),
], ids=["spine", "motion3", "voice-alone"])
def test_python_m_koma_rhubarb_writes_what_the_cli_writes(server, tmp_path, cues_name, name,
                                                         flags):
    """--rhubarb (the cues the C++ CLI writes for samples/voice.flac, JSON and TSV): with no
    --mode the server follows the cues' drawings, in both clients."""
    cues = tmp_path / cues_name
    run_cli("lipblink", "--audio", source_path("samples", "voice.flac"), "-o",
            str(tmp_path / "v.motion3.json"), "--cues", str(cues), "--server", server.address)
    inputs = [] if name is None else [source_path(*name.split("/"))]
    suffix = ".json" if name == "samples/hero.json" else ".motion3.json"
    expected, got = tmp_path / ("cli" + suffix), tmp_path / ("py" + suffix)
    run_cli("lipblink", *inputs, "--rhubarb", str(cues), "-o", str(expected), "--server",
            server.address, *flags)
    done = run_python_cli("lipblink", *inputs, "--rhubarb", str(cues), "-o", str(got),
                          "--server", server.address, *flags)
    assert done.returncode == 0, done.stderr
    assert got.read_bytes() == expected.read_bytes()

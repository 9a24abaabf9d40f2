"""XDTS exposure sheets (`--xdts`, `koma batch --xdts`, `result.write_xdts`) against the real
server: every file valid under the JSON Schema written from the published field list
(xdts.schema.json), read back by an independent reader that follows OpenToonz's import rules
(xdts_reference.py), per row equal to the drawing the answer's timing shows; the same bytes on
a rerun, from the C++ CLI and from the Python package."""
import csv
import io
import json
import math
import os
from fractions import Fraction

import pytest

import xdts_reference as ref
from conftest import run_cli, source_path

SAMPLES = ["samples/pitch.bvh", "samples/mocap_120fps.bvh"]
# Real captures no one here wrote (pybvh's fixtures, tests/testdata/README.md).
REAL_BVHS = ["tests/testdata/bvh_test1.bvh", "tests/testdata/bvh_test2.bvh",
             "tests/testdata/bvh_test3.bvh"]
SKELETAL_VARIANTS = [[], ["--timing-fps", "0"], ["--output-rate", "timing"],
                     ["--no-keep-length", "--hold-first"]]


def read_checked(path):
    """The sheet of an XDTS file, after checking the file's form: schema, one time table,
    entries in strictly increasing frames, an entry only where the cell changes, each Cell
    track closed by SYMBOL_NULL_CELL at frame `duration`."""
    with open(path, "rb") as f:
        data = f.read()
    document, _ = ref.load(data)
    ref.validate(document)
    table = document["timeTables"][0]
    assert len(document["timeTables"]) == 1
    for field in table["fields"]:
        for track in field["tracks"]:
            frames = [f["frame"] for f in track["frames"]]
            assert frames == sorted(set(frames)), "entries not in increasing frames"
            if field["fieldId"] == 0:
                values = [f["data"][0]["values"][0] for f in track["frames"]]
                assert all(a != b for a, b in zip(values, values[1:])), "an entry repeats a cell"
                assert values[-1] == "SYMBOL_NULL_CELL" and frames[-1] == table["duration"]
    return ref.read(data)


def drawings_from_sources(sources):
    """Cells named after the source frame shown, counted from 1 (what --timing-from reads)."""
    return [str(s + 1) for s in sources]


def timing_rows(timing_csv):
    """Per row of the sheet, the source frame the timing sheet shows there (per grid frame with
    a grid_frame column, repeating the frame before for a grid frame no output frame shows)."""
    rows = list(csv.DictReader(io.StringIO(timing_csv)))
    if "grid_frame" not in rows[0]:
        return [int(r["source_frame"]) for r in rows]
    by_grid = {}
    for r in rows:
        by_grid.setdefault(int(r["grid_frame"]), int(r["source_frame"]))
    out = []
    for g in range(max(by_grid) + 1):
        out.append(by_grid.get(g, out[-1] if out else None))
    return out


@pytest.mark.parametrize("clip", SAMPLES + REAL_BVHS)
@pytest.mark.parametrize("variant", SKELETAL_VARIANTS, ids=lambda v: " ".join(v) or "defaults")
def test_skeletal_sheet_shows_the_timing_map(server, client, tmp_path, clip, variant):
    xdts, again, timing = tmp_path / "a.xdts", tmp_path / "b.xdts", tmp_path / "t.csv"
    args = ["skeletal", source_path(clip), "--timing-only", "--timing", str(timing),
            "--server", server.address, *variant]
    run_cli(*args, "--xdts", str(xdts))
    run_cli(*args, "--xdts", str(again))
    assert xdts.read_bytes() == again.read_bytes()
    sheet = read_checked(xdts)
    name = os.path.basename(clip)[:-len(".bvh")]
    assert sheet["name"] == name
    assert [n for n, _ in sheet["cells"]] == [name]
    assert sheet["dialog"] == []
    sources = timing_rows(timing.read_text())
    assert sheet["duration"] == len(sources)
    assert sheet["cells"][0][1] == drawings_from_sources(sources)
    # The Python package writes the same bytes.
    options = {"timing_fps": 0} if "0" in variant else {}
    if "timing" in variant:
        options["output_rate"] = "TIMING_RATE"
    if "--no-keep-length" in variant:
        options.update(keep_length=False, order="HOLD_THEN_OMIT")
    result = client.retime_skeletal(source_path(clip), return_motion=False, **options)
    out = tmp_path / "py.xdts"
    result.write_xdts(out)
    assert out.read_bytes() == xdts.read_bytes()


def grid_rows(frames, fps, timing_fps=24):
    """Grid frames at or before the clip's last frame (exact for these rates)."""
    return math.floor(Fraction(frames - 1) * Fraction(timing_fps) / Fraction(fps)) + 1


ARM, TALK = "samples/arm_head.motion3.json", "samples/talk_blink.motion3.json"
# arm_head's curves are all in the default group "body"; talk_blink's eyes and mouth are in
# Live2D's default group "face" (timing groups), the head in "body".
CURVES_VARIANTS = [(ARM, []), (ARM, ["--timing-fps", "0"]),
                   (ARM, ["--on", "2", "--curve-on", "ParamAngleX=3"]),
                   (ARM, ["--tame", "2", "--tsume", "1.5", "--on", "1"]),
                   (TALK, []), (TALK, ["--timing-fps", "0"]),
                   (TALK, ["--group", "eyes=ParamEye*:on=2", "--curve-on", "ParamEyeLOpen=3"])]


def curves_track_name(result, i, ids, clip_name, tracks):
    """The layer expected for timing i: its timing group's name ("GROUP: IDS" for a curve
    override's timing inside a group); without groups the clip's name for a lone track, else
    the curves' ids."""
    response = result.response
    for group in response.timing_groups:
        if any(response.curves[c].timing == i for c in group.curves):
            return group.name if group.timing == i else f"{group.name}: {', '.join(ids)}"
    return clip_name if tracks == 1 else ", ".join(ids)


@pytest.mark.parametrize("clip,variant", CURVES_VARIANTS,
                         ids=lambda v: (" ".join(v) or "defaults") if isinstance(v, list)
                         else os.path.basename(v).split(".")[0])
def test_curves_sheet_has_a_track_per_timing(server, client, tmp_path, clip, variant):
    clip_name = os.path.basename(clip).split(".")[0]
    clip = source_path(clip)
    xdts, again = tmp_path / "a.xdts", tmp_path / "b.xdts"
    for out in (xdts, again):
        run_cli("curves", clip, "-o", str(tmp_path / "o.motion3.json"), "--xdts", str(out),
                "--server", server.address, *variant)
    assert xdts.read_bytes() == again.read_bytes()
    sheet = read_checked(xdts)
    options = {}
    if "--timing-fps" in variant:
        options["timing_fps"] = 0
    if "--on" in variant:
        options["frames_per_drawing"] = int(variant[variant.index("--on") + 1])
    if "--curve-on" in variant:
        curve_id, n = variant[variant.index("--curve-on") + 1].split("=")
        options["curve_overrides"] = [{"curve_id": curve_id, "frames_per_drawing": int(n)}]
    if "--group" in variant:
        options["timing_groups"] = [{"name": "eyes", "ids": ["ParamEye*"],
                                     "frames_per_drawing": 2}]
    if "--tame" in variant:
        options.update(tame=2.0, tsume=1.5)
    result = client.retime_curves(clip, **options)
    with open(clip, encoding="utf-8") as f:
        meta = json.load(f)["Meta"]
    frames = len(result.timing)
    rows = frames if result.timing_fps == 0 else grid_rows(frames, meta["Fps"])
    assert sheet["duration"] == rows
    used = [i for i in range(len(result.timings))
            if any(c["timing"] == i for c in result.curves.values())]
    assert len(sheet["cells"]) == len(used)
    assert bool(result.response.timing_groups) == (clip_name == "talk_blink")
    for (name, cells), i in zip(sheet["cells"], used):
        timing = result.timings[i]
        ids = [cid for cid, c in result.curves.items() if c["timing"] == i]
        want_name = curves_track_name(result, i, ids, clip_name, len(used)) + \
            f" (on {timing['frames_per_drawing']})"
        assert name == want_name
        if result.timing_fps == 0:
            want = [str(d + 1) for d in timing["drawing_of_frame"]]
        else:
            starts = timing["drawing_start_grid"]
            want = [str(sum(1 for s in starts if s <= g)) for g in range(rows)]
        assert cells == want, name
    if clip_name == "talk_blink":
        # Worked by hand: the layers are the groups (the drawing sheet's tracks).
        want = ({"body (on 3)", "eyes (on 2)", "eyes: ParamEyeLOpen (on 3)"} if "--group" in variant
                else {"body (on 3)", "face (on 3)"})
        assert {n for n, _ in sheet["cells"]} == want
    out = tmp_path / "py.xdts"
    result.write_xdts(out)
    assert out.read_bytes() == xdts.read_bytes()


LIPBLINK_VARIANTS = [[], ["--timing-fps", "0"], ["--mode", "follow", "--auto-blink", "1.5"],
                     ["--timing-fps", "0", "--unlinked-eyes", "--seed", "7"]]


def nearest(value, levels):
    best = 0
    for i in (1, 2):
        if abs(value - levels[i]) < abs(value - levels[best]):
            best = i
    return best


@pytest.mark.parametrize("variant", LIPBLINK_VARIANTS, ids=lambda v: " ".join(v) or "defaults")
def test_lipblink_sheet_mouth_eyes_and_dialog(server, client, tmp_path, variant):
    clip = source_path("samples/talk_blink.motion3.json")
    xdts, again = tmp_path / "a.xdts", tmp_path / "b.xdts"
    for out in (xdts, again):
        run_cli("lipblink", clip, "-o", str(tmp_path / "o.motion3.json"), "--xdts", str(out),
                "--server", server.address, *variant)
    assert xdts.read_bytes() == again.read_bytes()
    sheet = read_checked(xdts)
    options = {}
    if "--timing-fps" in variant:
        options["timing_fps"] = 0
    if "--mode" in variant:
        options["mouth"] = {"mode": "MOUTH_FOLLOW"}
        options["eyes"] = {"auto_blink": {"enabled": True, "mean_interval_s": 1.5}}
    if "--unlinked-eyes" in variant:
        options["eyes"] = {"linked": False}
        options["seed"] = 7
    result = client.lip_blink(clip, **options)
    frames = len(next(iter(result.curves.values())))
    with open(clip, encoding="utf-8") as f:
        fps = json.load(f)["Meta"]["Fps"]
    rows = frames if result.timing_fps == 0 else grid_rows(frames, fps)
    assert sheet["duration"] == rows
    tracks = dict(sheet["cells"])
    # The mouth: every hold's shape on its rows (1 closed, 2 mid, 3 open).
    shape_cell = {"MOUTH_CLOSED": "1", "MOUTH_MID": "2", "MOUTH_OPEN": "3"}
    for mouth in result.mouths:
        name = next(n for n in tracks if mouth["id"] in n.split(" (")[0].split(", "))
        assert name.endswith("(1 closed, 2 mid, 3 open)")
        for begin, length, shape in mouth["holds"]:
            assert tracks[name][begin:begin + length] == [shape_cell[shape]] * length
    # The eyes: closed rows 3 from C_start through C_end, then half-open 2 right after.
    for eye in result.eyes:
        name = next(n for n in tracks if eye["id"] in n.split(" (")[0].split(", "))
        assert name.endswith("(1 open, 2 half, 3 closed)")
        for b in eye["blinks"]:
            assert set(tracks[name][b["closed_begin"]:b["closed_end"] + 1]) == {"3"}
            assert tracks[name][b["closing_begin"]:b["closed_begin"]] == \
                ["1"] * (b["closed_begin"] - b["closing_begin"])
    if result.timing_fps == 0:
        # Counting source frames, every row is the drawing nearest the converted curve there:
        # inside holds and blinks exactly a level (core's repaint), elsewhere the input.
        for mouth in result.mouths:
            name = next(n for n in tracks if mouth["id"] in n.split(" (")[0].split(", "))
            levels = (mouth["closed_level"], mouth["mid_level"], mouth["open_level"])
            assert tracks[name] == [str(nearest(v, levels) + 1) for v in result.curves[mouth["id"]]]
        for eye in result.eyes:
            name = next(n for n in tracks if eye["id"] in n.split(" (")[0].split(", "))
            levels = (eye["open_level"], eye["mid_level"], eye["closed_level"])
            assert tracks[name] == [str(nearest(v, levels) + 1) for v in result.curves[eye["id"]]]
    # Dialog: the speech intervals, [clip name, "speech K"] then SYMBOL_HYPHEN each row.
    speech = [(b, min(e, rows)) for b, e in result.mouths[0]["speech"] if b < min(e, rows)]
    assert len(sheet["dialog"]) == 1
    name, lines = sheet["dialog"][0]
    assert name == "ParamMouthOpenY speech"
    assert [(b, e) for b, e, _ in lines] == speech
    assert [v for _, _, v in lines] == [["talk_blink", f"speech {k + 1}"] for k in range(len(lines))]
    out = tmp_path / "py.xdts"
    result.write_xdts(out)
    assert out.read_bytes() == xdts.read_bytes()


VOICE = "samples/voice.flac"
# LipBlink from a voice (--audio): a new motion at --voice-motion-fps (30, or 60), the voice
# into talk_blink (30 fps), counting source frames; and Rhubarb cues (--rhubarb) back in.
VOICE_VARIANTS = [[], ["--voice-motion-fps", "60", "--auto-blink", "1.5"],
                  ["--motion", TALK], ["--timing-fps", "0", "--mode", "follow"], ["--rhubarb"]]


@pytest.mark.parametrize("variant", VOICE_VARIANTS, ids=lambda v: " ".join(v) or "defaults")
def test_lipblink_from_a_voice_sheet_is_the_motion_written(server, client, tmp_path, variant):
    voice = source_path(VOICE)
    options, flags = {}, [source_path(f) if f == TALK else f for f in variant]
    if "--rhubarb" in variant:
        # The cues koma wrote for the recording, read back as the voice.
        cues = tmp_path / "voice.json"
        run_cli("lipblink", "--audio", voice, "-o", str(tmp_path / "c.motion3.json"), "--cues",
                str(cues), "--server", server.address)
        flags, voice_flag = [], ["--rhubarb", str(cues)]
        options["rhubarb_cues"] = str(cues)
    else:
        voice_flag = ["--audio", voice]
        options["audio"] = voice
    if "--voice-motion-fps" in variant:
        options.update(voice_motion_fps=60,
                       eyes={"auto_blink": {"enabled": True, "mean_interval_s": 1.5}})
    if "--timing-fps" in variant:
        options.update(timing_fps=0, mouth={"mode": "MOUTH_FOLLOW"})
    motion = tmp_path / "o.motion3.json"
    xdts, again = tmp_path / "a.xdts", tmp_path / "b.xdts"
    for out in (xdts, again):
        done = run_cli("lipblink", *voice_flag, "-o", str(motion), "--xdts", str(out),
                       "--server", server.address, *flags)
        assert f"exposure sheet (XDTS): {out}" in done.stdout
    assert xdts.read_bytes() == again.read_bytes()
    sheet = read_checked(xdts)
    source = source_path(TALK) if "--motion" in variant else None
    result = client.lip_blink(source, **options)
    # Rows: the grid frames of the motion written, at its own rate.
    with open(motion, encoding="utf-8") as f:
        meta = json.load(f)["Meta"]
    frames = len(next(iter(result.curves.values())))
    assert meta["Fps"] == (60 if "--voice-motion-fps" in variant else 30)
    rows = frames if result.timing_fps == 0 else grid_rows(frames, meta["Fps"])
    assert sheet["duration"] == rows
    tracks = dict(sheet["cells"])
    shape_cell = {"MOUTH_CLOSED": "1", "MOUTH_MID": "2", "MOUTH_OPEN": "3"}
    for mouth in result.mouths:
        name = next(n for n in tracks if mouth["id"] in n.split(" (")[0].split(", "))
        assert name.endswith("(1 closed, 2 mid, 3 open)")
        assert mouth["holds"], "the voice drew no mouth"
        for begin, length, shape in mouth["holds"]:
            end = min(begin + length, rows)
            assert tracks[name][begin:end] == [shape_cell[shape]] * (end - begin)
        if result.timing_fps == 0:
            levels = (mouth["closed_level"], mouth["mid_level"], mouth["open_level"])
            assert tracks[name] == [str(nearest(v, levels) + 1) for v in result.curves[mouth["id"]]]
    assert {"2", "3"} & set(tracks[next(n for n in tracks if "ParamMouthOpenY" in n)])
    for eye in result.eyes:
        name = next(n for n in tracks if eye["id"] in n.split(" (")[0].split(", "))
        for b in eye["blinks"]:
            assert set(tracks[name][b["closed_begin"]:b["closed_end"] + 1]) == {"3"}
    if "--voice-motion-fps" in variant:
        assert any(b["automatic"] for eye in result.eyes for b in eye["blinks"])
    # Dialog: the speech found in the recording, named after the motion, else the recording.
    speaker = "talk_blink" if "--motion" in variant else "voice"
    speech = [(b, min(e, rows)) for b, e in result.mouths[0]["speech"] if b < min(e, rows)]
    assert speech, "no speech found"
    name, lines = sheet["dialog"][0]
    assert [(b, e) for b, e, _ in lines] == speech
    assert [v for _, _, v in lines] == [[speaker, f"speech {k + 1}"] for k in range(len(lines))]
    assert sheet["name"] == speaker
    out = tmp_path / "py.xdts"
    result.write_xdts(out)
    assert out.read_bytes() == xdts.read_bytes()


def test_names_tools_choke_on_read_back_equal(server, client, tmp_path):
    """Quotes, newlines, backslashes and Japanese in file names and curve ids: valid JSON,
    read back equal."""
    weird = 'ピッチ "投球"\n\\1'
    clip = tmp_path / f"{weird}.bvh"
    clip.write_bytes(open(source_path("samples/pitch.bvh"), "rb").read())
    xdts = tmp_path / "sheet.xdts"
    run_cli("skeletal", str(clip), "--timing-only", "--xdts", str(xdts), "--server", server.address)
    sheet = read_checked(xdts)
    assert sheet["name"] == weird and sheet["cells"][0][0] == weird

    with open(source_path("samples/arm_head.motion3.json"), encoding="utf-8") as f:
        motion = json.load(f)
    ids = ['腕"X"', "頭\nY", "back\\slash\ttab"]
    for curve, new_id in zip(motion["Curves"], ids):
        curve["Id"] = new_id
    source = tmp_path / "口パク.motion3.json"
    source.write_text(json.dumps(motion, ensure_ascii=False), encoding="utf-8")
    xdts = tmp_path / "curves.xdts"
    run_cli("curves", str(source), "-o", str(tmp_path / "o.motion3.json"), "--xdts", str(xdts),
            "--curve-on", f"{ids[0]}=2", "--server", server.address)
    sheet = read_checked(xdts)
    assert sheet["name"] == "口パク"
    names = [n for n, _ in sheet["cells"]]
    assert names[1] == f"{ids[0]} (on 2)"
    assert all(i in names[0] for i in ids[1:])
    result = client.retime_curves(str(source), curve_overrides=[{"curve_id": ids[0],
                                                                 "frames_per_drawing": 2}])
    assert result.xdts().encode("utf-8") == xdts.read_bytes()


def test_batch_writes_each_clips_sheet_as_the_single_command(server, tmp_path):
    out = tmp_path / "out"
    clips = [source_path("samples/pitch.bvh"), source_path(REAL_BVHS[0]),
             source_path("samples/wave.glb")]
    run_cli("batch", "skeletal", *clips, "-o", str(out), "--xdts", "--server", server.address,
            "--quiet")
    for clip in clips:
        name, extension = os.path.splitext(os.path.basename(clip))
        single = tmp_path / f"{name}.xdts"
        run_cli("skeletal", clip, "-o", str(tmp_path / f"x{extension}"), "--xdts", str(single),
                "--server", server.address)
        assert (out / f"{name}.xdts").read_bytes() == single.read_bytes()
    run_cli("batch", "lipblink", source_path("samples/talk_blink.motion3.json"), "-o", str(out),
            "--xdts", "--server", server.address, "--quiet")
    single = tmp_path / "talk_blink.xdts"
    run_cli("lipblink", source_path("samples/talk_blink.motion3.json"), "-o",
            str(tmp_path / "t.motion3.json"), "--xdts", str(single), "--server", server.address)
    assert (out / "talk_blink.xdts").read_bytes() == single.read_bytes()
    # A recording: its new motion's sheet, as `koma lipblink --audio`.
    run_cli("batch", "lipblink", source_path(VOICE), "-o", str(out), "--xdts",
            "--server", server.address, "--quiet")
    single = tmp_path / "voice.xdts"
    run_cli("lipblink", "--audio", source_path(VOICE), "-o", str(tmp_path / "v.motion3.json"),
            "--xdts", str(single), "--server", server.address)
    assert (out / "voice.xdts").read_bytes() == single.read_bytes()


def long_bvh(path, frames):
    """A two-joint clip whose speed varies, `frames` frames at 30 fps."""
    lines = ["HIERARCHY", "ROOT Hips", "{", "\tOFFSET 0 0 0",
             "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
             "\tJOINT Arm", "\t{", "\t\tOFFSET 0 10 0", "\t\tCHANNELS 3 Zrotation Xrotation Yrotation",
             "\t\tEnd Site", "\t\t{", "\t\t\tOFFSET 0 10 0", "\t\t}", "\t}", "}", "MOTION",
             f"Frames: {frames}", "Frame Time: 0.0333333"]
    for k in range(frames):
        x = (k * k % 977) / 10.0
        lines.append(f"{x} 0 0 0 0 0 {(k * 37) % 360} 0 0")
    path.write_text("\n".join(lines) + "\n")


def test_a_100000_frame_clip(server, tmp_path):
    clip = tmp_path / "long.bvh"
    long_bvh(clip, 100000)
    xdts, again, timing = tmp_path / "a.xdts", tmp_path / "b.xdts", tmp_path / "t.csv"
    for out in (xdts, again):
        run_cli("skeletal", str(clip), "--timing-only", "--timing", str(timing), "--xdts", str(out),
                "--server", server.address, "--deadline", "120")
    assert xdts.read_bytes() == again.read_bytes()
    sheet = read_checked(xdts)
    sources = timing_rows(timing.read_text())
    assert sheet["duration"] == len(sources) == grid_rows(100000, 30)
    assert sheet["cells"][0][1] == drawings_from_sources(sources)


def test_gltf_sheet_is_the_first_animations_timing(server, client, tmp_path):
    clip = source_path("samples/wave.glb")
    xdts, timing = tmp_path / "a.xdts", tmp_path / "t.csv"
    run_cli("skeletal", clip, "-o", str(tmp_path / "o.glb"), "--timing", str(timing), "--xdts",
            str(xdts), "--server", server.address)
    sheet = read_checked(xdts)
    assert sheet["name"] == "wave" and [n for n, _ in sheet["cells"]] == ["wave"]
    assert sheet["cells"][0][1] == drawings_from_sources(timing_rows(timing.read_text()))
    out = tmp_path / "py.xdts"
    client.retime_skeletal(clip).write_xdts(out)
    assert out.read_bytes() == xdts.read_bytes()


def test_clip_name_is_the_cli_s_for_every_input_format():
    """koma._xdts.clip_name names a sheet as client/xdts_sheets.cc XdtsClipName does
    (tests/client/xdts_sheets_test.cc): the folder and any input format's extension off, from
    the format table, then a sheet's own extension."""
    from koma import _xdts
    cases = {("samples/pitch.bvh", "out/x.xdts"): "pitch", ("a/talk.motion3.json", ""): "talk",
             ("a/arm.CSV", ""): "arm", ("-", "out/sheet.xdts"): "sheet", ("-", "-"): "koma",
             ("rec/line_042.WAV", "x.xdts"): "line_042", ("line.cues.tsv", ""): "line.cues",
             ("mocap/take.FBX", ""): "take", ("wave.glb", ""): "wave",
             (".bvh", "out/s.xdts"): ".bvh"}
    for (source, fallback), want in cases.items():
        assert _xdts.clip_name(source, fallback) == want, (source, fallback)

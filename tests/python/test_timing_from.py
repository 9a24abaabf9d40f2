"""`--timing-from` (issue 46): koma's own XDTS sheet rewritten the way OpenToonz's exporter and
CLIP STUDIO PAINT write it, and hand-edited (a hold lengthened by 2 frames, two drawings
swapped, a drawing repeated later, a frame left blank), applied back through the C++ CLI and
the Python package against the real server. An independent evaluator (this file: the tests'
own XDTS reader, xdts_reference.py, and a BVH MOTION reader; not koma's code) checks that the
motion written shows exactly the drawing of the edited cell at every frame (a blank cell holds
the frame before, docs/usage.md). Also: sheet -> timing -> sheet is the identity for koma's
own sheets (XDTS and --timing CSV), one sheet gives a proxy and a final rig the same
frame-to-source map, and a sheet that does not fit gets the same message from both clients."""
import json
import os
import re

import pytest

import xdts_reference as ref
from conftest import run_cli, run_python_cli, source_path

IDENTIFIER = "exchangeDigitalTimeSheet Save Data"
# (clip, its source frames per grid frame on the 24 fps grid; 1: no grid)
CLIPS = [("samples/pitch.bvh", 1), ("samples/mocap_120fps.bvh", 5)]


# ---- the independent evaluator ---------------------------------------------------------

def bvh_frames(path):
    """Per frame, the MOTION values as floats."""
    with open(path) as f:
        text = f.read()
    motion = text[text.index("MOTION"):].splitlines()
    count = int(re.match(r"Frames:\s*(\d+)", motion[1]).group(1))
    rows = [[float(v) for v in line.split()] for line in motion[3:] if line.strip()]
    assert len(rows) == count
    return rows


def sheet_rows(path):
    """Per sheet row, the 0-based source frame the edited sheet shows: cell N is source frame
    N - 1; a blank cell holds the row before (blanks first: the first drawing)."""
    with open(path, "rb") as f:
        data = f.read()
    # The reference reader takes koma's LF line; CSP ends the identifier line with CRLF.
    sheet = ref.read(data.replace(b"\r\n", b"\n", 1))
    cells = sheet["cells"][0][1]
    shown = [int(c) - 1 if c else None for c in cells]
    first = next(s for s in shown if s is not None)
    out = []
    for s in shown:
        out.append(s if s is not None else (out[-1] if out else first))
    return out


def check_motion_shows_sheet(out_bvh, source_bvh, xdts, per_grid):
    """Every output frame k is a verbatim copy of the source frame its grid row's cell names
    (grid row of k = k // per_grid at the source rate)."""
    source, output, rows = bvh_frames(source_bvh), bvh_frames(out_bvh), sheet_rows(xdts)
    expected_length = min(len(source), len(rows) * per_grid)
    assert len(output) == expected_length, (len(output), expected_length)
    for k, values in enumerate(output):
        s = rows[k // per_grid]
        assert values == pytest.approx(source[s], rel=1e-9, abs=1e-9), \
            f"output frame {k} is not source frame {s} (sheet row {k // per_grid + 1})"


# ---- sheets as the tools write them ------------------------------------------------------

def entries(rows):
    """Cell entries where the cell changes, SYMBOL_NULL_CELL for a blank, the closing one."""
    out = []
    for r, s in enumerate(rows):
        if r > 0 and s == rows[r - 1]:
            continue
        out.append({"data": [{"id": 0, "values": ["SYMBOL_NULL_CELL" if s is None
                                                  else str(s + 1)]}], "frame": r})
    out.append({"data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}], "frame": len(rows)})
    return out


def opentoonz_sheet(rows, level):
    """OpenToonz's exporter (xdtsio.cpp, QJsonDocument): no header, no subversion or options,
    keys sorted, 4-space indent, the column named by its level."""
    document = {"timeTables": [{
        "duration": len(rows), "name": level,
        "fields": [{"fieldId": 0, "tracks": [{"frames": entries(rows), "trackNo": 0}]}],
        "timeTableHeaders": [{"fieldId": 0, "names": [level]}]}], "version": 5}
    return IDENTIFIER + "\n" + json.dumps(document, indent=4, sort_keys=True) + "\n"


def csp_sheet(rows):
    """CLIP STUDIO PAINT rebuilds the file from its timeline: a header (cut, scene), CRLF after
    the identifier, one line of JSON, the timeline's name, the animation folder's name ("A":
    matched by order), a Camerawork field, a Dialog header with no track."""
    document = {
        "header": {"cut": "1", "scene": "1"},
        "timeTables": [{
            "fields": [{"fieldId": 0, "tracks": [{"frames": entries(rows), "trackNo": 0}]},
                       {"fieldId": 5, "tracks": []}],
            "name": "\u30bf\u30a4\u30e0\u30e9\u30a4\u30f31",
            "timeTableHeaders": [{"fieldId": 0, "names": ["A"]}, {"fieldId": 3, "names": []},
                                 {"fieldId": 5, "names": []}],
            "duration": len(rows)}],
        "version": 5}
    return IDENTIFIER + "\r\n" + json.dumps(document, ensure_ascii=False,
                                            separators=(",", ":"))


def koma_sheet(rows, name):
    """koma's own layout (one entry a line), as a hand edit in a text editor leaves it."""
    lines = [IDENTIFIER, "{", '  "timeTables": [', "    {", f'      "duration": {len(rows)},',
             '      "fields": [', '        {', '          "fieldId": 0,', '          "tracks": [',
             "            {", '              "frames": [']
    items = entries(rows)
    for i, e in enumerate(items):
        lines.append("                " + json.dumps(e) + ("," if i + 1 < len(items) else ""))
    lines += ["              ],", '              "trackNo": 0', "            }", "          ]",
              "        }", "      ],", f'      "name": {json.dumps(name)},',
              '      "timeTableHeaders": [',
              f'        {{"fieldId": 0, "names": [{json.dumps(name)}]}}', "      ]", "    }",
              "  ],", '  "version": 5', "}"]
    return "\n".join(lines) + "\n"


# ---- the edits ---------------------------------------------------------------------------

def starts(rows):
    return [r for r in range(1, len(rows)) if rows[r] != rows[r - 1]]


def lengthen_hold(rows):
    """The hold before the second drawing change runs 2 frames longer (over the next one)."""
    r = starts(rows)[1]
    out = list(rows)
    out[r:r + 2] = [rows[r - 1]] * len(out[r:r + 2])
    return out


def swap_drawings(rows):
    """The second and third drawings swapped wherever they show."""
    a, b = rows[starts(rows)[0]], rows[starts(rows)[1]]
    return [b if s == a else a if s == b else s for s in rows]


def repeat_later(rows):
    """The first drawing shown again for two frames near the end."""
    r = len(rows) - 4
    out = list(rows)
    out[r:r + 2] = [rows[0], rows[0]]
    return out


def blank_frame(rows):
    """One frame in the middle left blank (SYMBOL_NULL_CELL)."""
    out = list(rows)
    out[len(rows) // 2] = None
    return out


def all_edits(rows):
    return blank_frame(repeat_later(swap_drawings(lengthen_hold(rows))))


EDITS = {"as written": lambda rows: rows, "hold lengthened by 2": lengthen_hold,
         "two drawings swapped": swap_drawings, "a drawing repeated later": repeat_later,
         "a frame left blank": blank_frame, "all four": all_edits}
LAYOUTS = {"opentoonz": lambda rows, name: opentoonz_sheet(rows, name),
           "csp": lambda rows, name: csp_sheet(rows),
           "hand-edited": koma_sheet}


def written_rows(tmp_path, server, clip):
    """koma's sheet of the clip's computed timing, as its rows of source frames."""
    xdts = tmp_path / "koma.xdts"
    run_cli("skeletal", clip, "--timing-only", "--xdts", str(xdts), "--server", server.address)
    return sheet_rows(xdts), xdts


@pytest.mark.parametrize("clip,per_grid", CLIPS, ids=lambda v: str(v).split("/")[-1])
@pytest.mark.parametrize("layout", LAYOUTS)
def test_edited_sheets_are_shown_frame_by_frame(server, client, tmp_path, clip, per_grid, layout):
    clip = source_path(clip)
    name = os.path.basename(clip)[:-len(".bvh")]
    rows, _ = written_rows(tmp_path, server, clip)
    for edit, change in EDITS.items():
        edited = change(rows)
        assert edit == "as written" or edited != rows
        sheet = tmp_path / f"{layout}-{len(edit)}.xdts"
        sheet.write_bytes(LAYOUTS[layout](edited, name).encode("utf-8"))
        out, py_out = tmp_path / "out.bvh", tmp_path / "py.bvh"
        run_cli("skeletal", clip, "-o", str(out), "--timing-from", str(sheet),
                "--server", server.address)
        check_motion_shows_sheet(out, clip, sheet, per_grid)
        client.retime_skeletal(clip, timing_from=sheet).write(py_out)
        assert py_out.read_bytes() == out.read_bytes(), f"{edit}: Python and C++ differ"


@pytest.mark.parametrize("clip,per_grid", CLIPS, ids=lambda v: str(v).split("/")[-1])
def test_koma_sheets_round_trip(server, tmp_path, clip, per_grid):
    """sheet -> timing -> sheet: the XDTS and the --timing CSV koma writes, applied back, give
    the same sheets and the same motion."""
    clip = source_path(clip)
    a = {k: tmp_path / f"a.{k}" for k in ("bvh", "xdts", "csv")}
    run_cli("skeletal", clip, "-o", str(a["bvh"]), "--xdts", str(a["xdts"]), "--timing",
            str(a["csv"]), "--server", server.address)
    for source in ("xdts", "csv"):
        b = {k: tmp_path / f"b-{source}.{k}" for k in ("bvh", "xdts", "csv")}
        run_cli("skeletal", clip, "-o", str(b["bvh"]), "--xdts", str(b["xdts"]), "--timing",
                str(b["csv"]), "--timing-from", str(a[source]), "--server", server.address)
        assert b["xdts"].read_bytes() == a["xdts"].read_bytes(), source
        assert b["bvh"].read_bytes() == a["bvh"].read_bytes(), source
        # The CSV's source frames come back; its kinds say HELD where a computed timing says
        # DUPLICATE (a given timing has no duplicates).
        def columns(path):
            return [line.split(",")[:2] for line in path.read_text().splitlines()]
        assert columns(b["csv"]) == columns(a["csv"]), source


def final_rig(source, target):
    """The same motion on another skeleton: every OFFSET scaled by 1.25 (a final rig beside the
    proxy)."""
    text = source.read_text() if hasattr(source, "read_text") else open(source).read()
    def scale(match):
        values = " ".join(f"{float(v) * 1.25:.4f}" for v in match.group(2).split())
        return f"{match.group(1)}{values}"
    target.write_text(re.sub(r"(OFFSET\s+)([-0-9.eE ]+)", scale, text))


def test_one_sheet_gives_proxy_and_final_rig_the_same_map(server, client, tmp_path):
    proxy = source_path("samples/pitch.bvh")
    final = tmp_path / "pitch_final.bvh"
    final_rig(proxy, final)
    rows, _ = written_rows(tmp_path, server, proxy)
    sheet = tmp_path / "edited.xdts"
    sheet.write_text(koma_sheet(all_edits(rows), "pitch"))
    maps = []
    for clip in (proxy, final):
        csv = tmp_path / "timing.csv"
        run_cli("skeletal", str(clip), "--timing-only", "--timing", str(csv), "--timing-from",
                str(sheet), "--server", server.address)
        maps.append([line.split(",")[1] for line in csv.read_text().splitlines()[1:]])
        result = client.retime_skeletal(str(clip), timing_from=sheet, return_motion=False)
        assert [int(s) for s in maps[-1]] == list(result.response.source_frames)
    assert maps[0] == maps[1]
    assert [int(s) for s in maps[0]] == sheet_rows(sheet)
    # The final rig's motion shows the same drawings, on its own skeleton.
    out = tmp_path / "final_out.bvh"
    run_cli("skeletal", str(final), "-o", str(out), "--timing-from", str(sheet),
            "--server", server.address)
    check_motion_shows_sheet(out, final, sheet, 1)


def both_fail(clip, sheet, server):
    """The C++ and the Python CLI's messages for a sheet that does not fit (equal)."""
    cpp = run_cli("skeletal", clip, "-o", os.devnull, "--timing-from", str(sheet), "--server",
                  server.address, check=False)
    py = run_python_cli("skeletal", clip, "-o", os.devnull, "--timing-from", str(sheet),
                        "--server", server.address)
    assert cpp.returncode == 1 and py.returncode == 1, (cpp.stderr, py.stderr)
    return cpp.stderr.strip(), py.stderr.strip()


def test_sheets_that_do_not_fit_name_track_frame_and_cell(server, tmp_path):
    clip = source_path("samples/pitch.bvh")
    rows, koma = written_rows(tmp_path, server, clip)
    text = koma.read_text()
    cases = {}
    # A cell that names no drawing (a source frame past the clip's 130).
    cases["cell.xdts"] = (koma_sheet(rows[:20] + [499] + rows[21:], "pitch"),
                          'track "pitch", frame 21: cell "500" names no drawing (cells are the '
                          "clip's source frames 1 to 130)")
    # A letter-suffixed cell OpenToonz allows (an inserted drawing koma has not).
    cases["suffix.xdts"] = (text.replace('"values": ["1"]', '"values": ["1a"]', 1),
                            'track "pitch", frame 1: cell "1a" names no drawing')
    # Longer than the clip.
    cases["long.xdts"] = (koma_sheet(rows + [rows[-1]] * 3, "pitch"),
                          f'track "pitch", frame 131: cell "{rows[-1] + 1}" is past the clip\'s '
                          "end: the sheet has 133 frames, the clip 130")
    # A second Cell track no track of the clip takes.
    two = json.loads(text.split("\n", 1)[1])
    table = two["timeTables"][0]
    table["fields"][0]["tracks"].append(dict(table["fields"][0]["tracks"][0], trackNo=1))
    table["timeTableHeaders"][0]["names"].append("BG")
    cases["track.xdts"] = (IDENTIFIER + "\n" + json.dumps(two),
                           'track "BG" (Cell track 2 of 2): no such track: the clip\'s tracks '
                           'are "pitch"')
    cases["bad.csv"] = ("output_frame,source_frame\n0,0\n1,-3\n",
                        'line 3: source_frame "-3" is not a whole number >= 0')
    cases["grid.csv"] = ("output_frame,source_frame,kind,time_s,grid_frame\n0,0,HELD,0,0\n"
                         "1,1,HELD,0,1\n2,2,HELD,0,1\n",
                         'line 4: grid_frame 1 shows source_frame 2 here and a different one')
    # On the film grid: mocap_120fps's 61 frames are 13 grid frames at 24 fps.
    mocap = source_path("samples/mocap_120fps.bvh")
    cases["grid_long.xdts"] = (koma_sheet([0] * 14, "mocap_120fps"),
                               'track "mocap_120fps", frame 14: cell "1" is past the clip\'s end: '
                               "the sheet has 14 frames, the clip 13 on the 24 fps grid")
    for file_name, (content, message) in cases.items():
        sheet = tmp_path / file_name
        sheet.write_text(content)
        cpp, py = both_fail(mocap if file_name == "grid_long.xdts" else clip, sheet, server)
        assert cpp.startswith(f"koma: {sheet}: {message}"), cpp
        assert py == cpp


def test_extra_time_tables_are_ignored_with_a_warning(server, client, tmp_path):
    clip = source_path("samples/pitch.bvh")
    rows, koma = written_rows(tmp_path, server, clip)
    document = json.loads(koma.read_text().split("\n", 1)[1])
    edited = json.loads(opentoonz_sheet(swap_drawings(rows), "pitch").split("\n", 1)[1])
    document["timeTables"] = edited["timeTables"] + document["timeTables"]
    sheet = tmp_path / "two_tables.xdts"
    sheet.write_text(IDENTIFIER + "\n" + json.dumps(document))
    out = tmp_path / "out.bvh"
    done = run_cli("skeletal", clip, "-o", str(out), "--timing-from", str(sheet), "--server",
                   server.address)
    warning = f'{sheet}: 1 extra time table ignored: koma reads the first ("pitch")'
    assert warning in done.stdout + done.stderr
    assert f"given      the timing of {sheet}" in done.stdout
    check_motion_shows_sheet(out, clip, sheet, 1)  # the first table's cells
    assert warning in client.retime_skeletal(clip, timing_from=sheet).warnings


def test_batch_applies_one_sheet_or_each_clips_own(server, tmp_path):
    """koma batch skeletal --timing-from SHEET: one timing on every clip (a proxy's on the
    final rig); --timing-from FOLDER: each clip's NAME.xdts (or NAME.timing.csv) there."""
    clips = tmp_path / "clips"
    clips.mkdir()
    proxy = source_path("samples/pitch.bvh")
    (clips / "pitch.bvh").write_text(open(proxy).read())
    final_rig(proxy, clips / "pitch_final.bvh")
    rows, _ = written_rows(tmp_path, server, proxy)
    sheet = tmp_path / "edited.xdts"
    sheet.write_text(opentoonz_sheet(all_edits(rows), "pitch"))
    out = tmp_path / "one"
    run_cli("batch", "skeletal", str(clips), "-o", str(out), "--timing-from", str(sheet),
            "--server", server.address)
    for name in ("pitch", "pitch_final"):
        check_motion_shows_sheet(out / f"{name}.bvh", clips / f"{name}.bvh", sheet, 1)
    # A folder of sheets: pitch's is edited, pitch_final's is the --timing CSV of another edit.
    sheets = tmp_path / "sheets"
    sheets.mkdir()
    (sheets / "pitch.xdts").write_text(sheet.read_text())
    other = swap_drawings(rows)
    (sheets / "pitch_final.timing.csv").write_text(
        "output_frame,source_frame\n" + "".join(f"{i},{s}\n" for i, s in enumerate(other)))
    (sheets / "pitch_final.xdts.expected").write_text(koma_sheet(other, "pitch_final"))
    out = tmp_path / "each"
    run_cli("batch", "skeletal", str(clips), "-o", str(out), "--timing-from", str(sheets),
            "--server", server.address)
    check_motion_shows_sheet(out / "pitch.bvh", clips / "pitch.bvh", sheet, 1)
    check_motion_shows_sheet(out / "pitch_final.bvh", clips / "pitch_final.bvh",
                             sheets / "pitch_final.xdts.expected", 1)
    # A rerun is up to date; an edited sheet redoes the clips.
    rerun = run_cli("batch", "skeletal", str(clips), "-o", str(out), "--timing-from",
                    str(sheets), "--server", server.address)
    assert "0 done, 2 up to date" in rerun.stderr + rerun.stdout
    (sheets / "pitch.xdts").write_text(koma_sheet(repeat_later(rows), "pitch"))
    rerun = run_cli("batch", "skeletal", str(clips), "-o", str(out), "--timing-from",
                    str(sheets), "--server", server.address)
    assert "2 done, 0 up to date" in rerun.stderr + rerun.stdout
    check_motion_shows_sheet(out / "pitch.bvh", clips / "pitch.bvh", sheets / "pitch.xdts", 1)
    (sheets / "pitch_final.timing.csv").unlink()
    done = run_cli("batch", "skeletal", str(clips), "-o", str(tmp_path / "none"),
                   "--timing-from", str(sheets), "--server", server.address, check=False)
    assert done.returncode == 1
    assert f"no sheet for {clips / 'pitch_final.bvh'}" in done.stderr

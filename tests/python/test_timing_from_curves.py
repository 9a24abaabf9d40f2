"""`koma curves|lipblink --timing-from` (issue 46): koma's own curves and lipblink XDTS sheets
rewritten the way OpenToonz and CLIP STUDIO PAINT write them and hand-edited (the sheet
writers and edits of test_timing_from.py), applied back through the C++ CLI against the real
server. The independent evaluator (this file, the tests' own XDTS reader xdts_reference.py,
and the CSV the CLI writes) checks every output frame: a curves track's cell n shows the
values the unedited answer shows at drawing n's first frame; a lipblink row the animator
changed shows the level of its new cell, an unchanged row the unedited answer's value. Also
sheet -> timing -> sheet is the identity (on the 24 fps grid and without), and a sheet that
does not fit gets an error naming the track, frame and cells."""
import csv
import json

import pytest

import xdts_reference as ref
from conftest import run_cli, run_python_cli, source_path
from test_timing_from import EDITS, IDENTIFIER, LAYOUTS, koma_sheet

CURVES = "samples/arm_head.motion3.json"
LIPBLINK = "samples/talk_blink.motion3.json"


def sheet_tracks(path):
    """Per Cell track: (name, per row the 0-based drawing; a blank holds the row before)."""
    with open(path, "rb") as f:
        sheet = ref.read(f.read().replace(b"\r\n", b"\n", 1))
    out = []
    for name, cells in sheet["cells"]:
        shown = [int(c) - 1 if c else None for c in cells]
        first = next(s for s in shown if s is not None)
        rows = []
        for s in shown:
            rows.append(s if s is not None else (rows[-1] if rows else first))
        out.append((name, rows))
    return out


def csv_rows(path):
    """Per frame, {curve id: value}."""
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in row.items() if k != "frame"} for row in csv.DictReader(f)]


def written(tmp_path, server, command, clip, *flags):
    """koma's unedited answer (CSV) and its sheet."""
    out, xdts = tmp_path / f"{command}.csv", tmp_path / f"{command}.xdts"
    run_cli(command, clip, "-o", str(out), "--xdts", str(xdts), *flags,
            "--server", server.address)
    return csv_rows(out), sheet_tracks(xdts), xdts


def applied(tmp_path, server, client, command, clip, sheet_text, *flags):
    """The answer with --timing-from the sheet `sheet_text` (CSV rows), checked to be the
    same motion3.json bytes from the Python package (retime_curves / lip_blink timing_from=)."""
    sheet, out = tmp_path / "edited.xdts", tmp_path / "applied.csv"
    motion, py_motion = tmp_path / "applied.motion3.json", tmp_path / "py.motion3.json"
    sheet.write_bytes(sheet_text.encode("utf-8"))
    for path in (out, motion):
        run_cli(command, clip, "-o", str(path), "--timing-from", str(sheet), *flags,
                "--server", server.address)
    call = client.retime_curves if command == "curves" else client.lip_blink
    call(clip, timing_fps=float(flags[1]), timing_from=sheet).write(py_motion)
    assert py_motion.read_bytes() == motion.read_bytes(), "Python and C++ differ"
    return csv_rows(out), sheet


@pytest.mark.parametrize("layout", LAYOUTS)
def test_curves_sheets_edited_are_shown_frame_by_frame(server, client, tmp_path, layout):
    clip = source_path(CURVES)
    flags = ("--timing-fps", "0")  # one sheet row per output frame
    unedited, [(name, rows)], _ = written(tmp_path, server, "curves", clip, *flags)
    first_frame = {}
    for r, d in enumerate(rows):
        first_frame.setdefault(d, r)
    for edit, change in EDITS.items():
        edited = change(rows)
        values, sheet = applied(tmp_path, server, client, "curves", clip,
                                LAYOUTS[layout](edited, name), *flags)
        [(_, shown)] = sheet_tracks(sheet)
        assert len(values) == len(unedited) == len(shown)
        for k, frame in enumerate(values):
            expected = unedited[first_frame[shown[k]]]
            assert frame == pytest.approx(expected, abs=1e-9), \
                f"{edit}: frame {k} does not show drawing {shown[k] + 1}"


def lipblink_edits(tracks):
    """The edits on the mouth track; the eye track keeps its cells, but its second blink's
    closed run lengthened by 1 (a blink koma can paint: closed c + 1, half h <= c)."""
    mouth, eyes = tracks[0][1], tracks[1][1]
    first_closed = [r for r in range(1, len(eyes)) if eyes[r] == 2 and eyes[r - 1] == 0]
    longer_blink = list(eyes)
    longer_blink[first_closed[-1] - 1] = 2
    for edit, change in EDITS.items():
        yield edit, [change(mouth), eyes]
    yield "a blink closed 1 frame longer", [mouth, longer_blink]


def two_track_sheet(tracks, edited, layout="hand-edited"):
    """A sheet of several Cell tracks in a layout of test_timing_from.py (whose writers write
    one): each track written alone, then joined into the first one's field, in that layout's
    JSON style (OpenToonz: sorted keys, 4-space indent; CSP: one line after a CRLF; koma's
    own: one entry a line, hand-edited)."""
    documents = []
    for (name, _), rows in zip(tracks, edited):
        text = LAYOUTS[layout](rows, name)
        identifier, body = text.split("\n", 1)
        documents.append(json.loads(body))
    first = documents[0]["timeTables"][0]
    for k, document in enumerate(documents[1:], start=1):
        table = document["timeTables"][0]
        track = table["fields"][0]["tracks"][0]
        track["trackNo"] = k
        first["fields"][0]["tracks"].append(track)
        first["timeTableHeaders"][0]["names"] += table["timeTableHeaders"][0]["names"]
    if layout == "opentoonz":
        return IDENTIFIER + "\n" + json.dumps(documents[0], indent=4, sort_keys=True) + "\n"
    if layout == "csp":
        return IDENTIFIER + "\r\n" + json.dumps(documents[0], ensure_ascii=False,
                                                 separators=(",", ":"))
    return IDENTIFIER + "\n" + json.dumps(documents[0], indent=2) + "\n"


@pytest.mark.parametrize("layout", LAYOUTS)
def test_lipblink_sheets_edited_are_shown_frame_by_frame(server, client, tmp_path, layout):
    clip = source_path(LIPBLINK)
    flags = ("--timing-fps", "0")
    unedited, tracks, _ = written(tmp_path, server, "lipblink", clip, *flags)
    assert [n for n, _ in tracks] == ["ParamMouthOpenY (1 closed, 2 mid, 3 open)",
                                      "ParamEyeLOpen, ParamEyeROpen (1 open, 2 half, 3 closed)"]
    curves_of = [["ParamMouthOpenY"], ["ParamEyeLOpen", "ParamEyeROpen"]]
    # A cell's level: the value the unedited answer shows most often where the cell shows.
    levels = {}  # per curve, per cell
    for (_, rows), ids in zip(tracks, curves_of):
        for curve in ids:
            per_cell = {}
            for r, c in enumerate(rows):
                per_cell.setdefault(c, []).append(unedited[r][curve])
            levels[curve] = {c: max(set(v), key=v.count) for c, v in per_cell.items()}
    for edit, edited in lipblink_edits(tracks):
        values, sheet = applied(tmp_path, server, client, "lipblink", clip,
                                two_track_sheet(tracks, edited, layout), *flags)
        shown = sheet_tracks(sheet)
        assert len(values) == len(unedited)
        for t, ids in enumerate(curves_of):
            for r, cell in enumerate(shown[t][1]):
                for curve in ids:
                    if cell == tracks[t][1][r]:
                        expected = unedited[r][curve]
                    else:
                        expected = levels[curve][cell]
                    assert values[r][curve] == pytest.approx(expected, abs=1e-9), \
                        f"{edit}: {curve} frame {r} does not show cell {cell + 1}"


@pytest.mark.parametrize("command,clip", [("curves", CURVES), ("lipblink", LIPBLINK)])
@pytest.mark.parametrize("timing_fps", ["24", "0"])
def test_koma_sheets_round_trip(server, tmp_path, command, clip, timing_fps):
    """sheet -> timing -> sheet: koma's own sheet applied back gives the same sheet and the
    same motion bytes."""
    clip = source_path(clip)
    flags = ["--timing-fps", timing_fps, "--server", server.address]
    a, b = tmp_path / "a.motion3.json", tmp_path / "b.motion3.json"
    sheet_a, sheet_b = tmp_path / "a.xdts", tmp_path / "b.xdts"
    run_cli(command, clip, "-o", str(a), "--xdts", str(sheet_a), *flags)
    done = run_cli(command, clip, "-o", str(b), "--xdts", str(sheet_b), "--timing-from",
                   str(sheet_a), *flags)
    assert f"  given: the timing of {sheet_a}\n" in done.stdout
    assert sheet_b.read_bytes() == sheet_a.read_bytes()
    assert b.read_bytes() == a.read_bytes()
    # --send-file: the file travels whole, the sheet's timing with it.
    run_cli(command, clip, "-o", str(b), "--send-file", "--timing-from", str(sheet_a), *flags)
    assert b.read_bytes() == a.read_bytes()


def test_sheets_that_do_not_fit(server, tmp_path):
    lip = source_path(LIPBLINK)
    _, tracks, _ = written(tmp_path, server, "lipblink", lip)
    closed = tracks[1][1].index(2)
    sheet = tmp_path / "bad.xdts"
    # Runs of non-open eye cells koma paints no blink as: 4 half after 1 closed (at most 3,
    # at most as many as closed), half before closed, closed straight to open.
    for run, shown in [([2, 1, 1, 1, 1], "32222"), ([1, 2, 2, 1], "2332"), ([2, 2], "33")]:
        eyes = list(tracks[1][1])
        eyes[closed - 1:closed + 8] = [0] * 9
        eyes[closed:closed + len(run)] = run
        sheet.write_text(two_track_sheet(tracks, [tracks[0][1], eyes]))
        done = run_cli("lipblink", lip, "-o", str(tmp_path / "x.csv"), "--timing-from",
                       str(sheet), "--server", server.address, check=False)
        py = run_python_cli("lipblink", lip, "-o", str(tmp_path / "x.motion3.json"),
                            "--timing-from", str(sheet), "--server", server.address)
        assert done.returncode != 0 and py.returncode != 0
        assert done.stderr.split(": ", 1)[1] in py.stderr, (done.stderr, py.stderr)
        # A long track name is cut to 40 characters in messages (formats/error_text.h).
        assert (f'bad.xdts: track "{tracks[1][0][:40]}"..., frame {closed + 1}: cells {shown} '
                "are no blink koma paints") in done.stderr, done.stderr

    curves = source_path(CURVES)
    _, [(name, rows)], _ = written(tmp_path, server, "curves", curves)
    for cells, message in [
            (rows[:-1], f'track "{name}", frame {len(rows) - 1}: the sheet ends before the clip'),
            (rows + [0], f'track "{name}", frame {len(rows) + 1}: cell "1" is past the clip'),
            ([99] + rows[1:], f'track "{name}", frame 1: cell "100" names no drawing')]:
        sheet.write_text(koma_sheet(cells, name))
        done = run_cli("curves", curves, "-o", str(tmp_path / "x.csv"), "--timing-from",
                       str(sheet), "--server", server.address, check=False)
        assert done.returncode != 0 and message in done.stderr, done.stderr
        py = run_python_cli("curves", curves, "-o", str(tmp_path / "x.motion3.json"),
                            "--timing-from",
                            str(sheet), "--server", server.address)
        assert py.returncode != 0 and done.stderr.split(": ", 1)[1] in py.stderr, py.stderr
    done = run_cli("curves", curves, "-o", str(tmp_path / "x.csv"), "--timing-from",
                   str(tmp_path / "missing.xdts"), "--server", server.address, check=False)
    assert done.returncode != 0 and "missing.xdts" in done.stderr


@pytest.mark.parametrize("command,clip", [("curves", CURVES), ("lipblink", LIPBLINK)])
def test_batch_refuses_a_sheet_for_curves_and_lipblink(server, tmp_path, command, clip):
    """Not applied per clip in a batch yet: refused (exit 2) rather than ignored."""
    done = run_cli("batch", command, source_path(clip), "--output-dir", str(tmp_path / "out"),
                   "--timing-from", str(tmp_path / "edit.xdts"), "--server", server.address,
                   check=False)
    assert done.returncode == 2
    assert "--timing-from: koma batch applies sheets to skeletal clips only" in done.stderr
    assert not (tmp_path / "out").exists()

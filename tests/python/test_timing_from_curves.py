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
from test_timing_from import EDITS, IDENTIFIER, LAYOUTS, koma_sheet, swap_drawings

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


def drawing_sheet(path):
    """koma curves --timing's drawing sheet: (header, rows as lists of text)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def spreadsheet_edit(header, rows, edited, columns=("drawing", "source_frame")):
    """The sheet with column `columns[0]` set to the edited drawings (None: both cells
    emptied, a blank frame) and its source_frame to that drawing's, as a spreadsheet saves
    it: CRLF line ends, every cell quoted, time_s and keys left stale."""
    drawing, source = header.index(columns[0]), header.index(columns[1])
    tau = {int(r[drawing]): r[source] for r in rows}
    out = [list(header)]
    for row, d in zip(rows, edited):
        row = list(row)
        row[drawing], row[source] = ("", "") if d is None else (str(d), tau[d])
        out.append(row)
    return "".join(",".join(f'"{v}"' for v in row) + "\r\n" for row in out)


def shown_drawings(edited):
    """Per row the drawing shown: a blank holds the one before."""
    out = []
    for d in edited:
        out.append(d if d is not None else out[-1])
    return out


def test_curves_drawing_sheet_csv_edited_is_shown_frame_by_frame(server, client, tmp_path):
    """The drawing sheet CSV (--timing) edited in a spreadsheet with the four edits: every
    output frame shows the unedited answer's values of the row's drawing; the Python package
    gives the same bytes."""
    clip = source_path(CURVES)
    flags = ("--timing-fps", "0")  # the CSV has a row per output frame
    out, sheet = tmp_path / "unedited.csv", tmp_path / "timing.csv"
    run_cli("curves", clip, "-o", str(out), "--timing", str(sheet), *flags,
            "--server", server.address)
    unedited = csv_rows(out)
    header, rows = drawing_sheet(sheet)
    drawings = [int(r[1]) for r in rows]
    first_frame = {}
    for r, d in enumerate(drawings):
        first_frame.setdefault(d, r)
    edited_csv, values_csv = tmp_path / "edited.csv", tmp_path / "applied.csv"
    motion, py_motion = tmp_path / "applied.motion3.json", tmp_path / "py.motion3.json"
    for edit, change in EDITS.items():
        edited = change(drawings)
        assert (edited != drawings) == (edit != "as written"), edit
        edited_csv.write_text(spreadsheet_edit(header, rows, edited), newline="")
        for path in (values_csv, motion):
            run_cli("curves", clip, "-o", str(path), "--timing-from", str(edited_csv), *flags,
                    "--server", server.address)
        client.retime_curves(clip, timing_fps=0.0, timing_from=edited_csv).write(py_motion)
        assert py_motion.read_bytes() == motion.read_bytes(), f"{edit}: Python and C++ differ"
        values, shown = csv_rows(values_csv), shown_drawings(edited)
        assert len(values) == len(unedited) == len(shown)
        for k, frame in enumerate(values):
            assert frame == pytest.approx(unedited[first_frame[shown[k]]], abs=1e-9), \
                f"{edit}: frame {k} does not show drawing {shown[k]}"


def test_curves_drawing_sheet_csv_of_two_groups(server, tmp_path):
    """Two timing groups (columns drawing and arms_drawing): the CSV applied back gives the
    same bytes; a swap in the arms column shows on the arms' curves only."""
    clip = source_path(CURVES)
    flags = ("--timing-fps", "0", "--group", "arms=ParamArm*:on=2", "--server", server.address)
    out, sheet, again = tmp_path / "a.csv", tmp_path / "timing.csv", tmp_path / "b.csv"
    run_cli("curves", clip, "-o", str(out), "--timing", str(sheet), *flags)
    header, rows = drawing_sheet(sheet)
    assert header[:6] == ["output_frame", "drawing", "source_frame", "time_s", "arms_drawing",
                          "arms_source_frame"], header
    run_cli("curves", clip, "-o", str(again), "--timing-from", str(sheet), *flags)
    assert again.read_bytes() == out.read_bytes()
    unedited = csv_rows(out)
    arms = [int(r[4]) for r in rows]
    edited = swap_drawings(arms)
    edited_csv = tmp_path / "edited.csv"
    edited_csv.write_text(spreadsheet_edit(header, rows, edited,
                                           ("arms_drawing", "arms_source_frame")), newline="")
    run_cli("curves", clip, "-o", str(again), "--timing-from", str(edited_csv), *flags)
    first_frame = {}
    for r, d in enumerate(arms):
        first_frame.setdefault(d, r)
    for k, frame in enumerate(csv_rows(again)):
        for curve, value in frame.items():
            source = first_frame[edited[k]] if curve.startswith("ParamArm") else k
            assert value == pytest.approx(unedited[source][curve], abs=1e-9), (curve, k)


def test_drawing_sheet_csv_that_does_not_fit(server, tmp_path):
    """A bad row names the file, line, track (column), frame and value, the same from C++
    and Python; a CSV for the wrong command or on a film grid is refused saying why."""
    clip = source_path(CURVES)
    flags = ("--timing-fps", "0", "--server", server.address)
    sheet = tmp_path / "timing.csv"
    run_cli("curves", clip, "-o", str(tmp_path / "a.csv"), "--timing", str(sheet), *flags)
    header, rows = drawing_sheet(sheet)
    last = max(int(r[1]) for r in rows)
    bad = tmp_path / "bad.csv"

    def with_row(index, column, value):
        edited = [list(r) for r in rows]
        edited[index][column] = value
        return "\n".join(",".join(r) for r in [header] + edited) + "\n"

    for text, message in [
            (with_row(4, 1, str(last + 1)),
             f'bad.csv: line 6: track "drawing", frame 5: drawing {last + 1} names no drawing '
             f"(the drawings are 0 to {last})"),
            (with_row(4, 1, "two"), 'bad.csv: line 6: drawing "two" is not a whole number'),
            (with_row(4, 2, "99"),
             f'bad.csv: line 6: track "drawing", frame 5: drawing {rows[4][1]} is source frame '
             f'{rows[4][2]}, the row\'s source_frame says "99" (koma reads the drawing column'),
            ("\n".join(",".join(r) for r in [header] + rows[:-1]) + "\n",
             f'track "drawing", frame {len(rows) - 1}: the sheet ends before the clip')]:
        bad.write_text(text)
        done = run_cli("curves", clip, "-o", str(tmp_path / "x.csv"), "--timing-from",
                       str(bad), *flags, check=False)
        assert done.returncode != 0 and message in done.stderr, done.stderr
        py = run_python_cli("curves", clip, "-o", str(tmp_path / "x.motion3.json"),
                            "--timing-from", str(bad), *flags)
        assert py.returncode != 0 and done.stderr.split(": ", 1)[1] in py.stderr, py.stderr
    # A cleared source_frame is no disagreement: the drawing column is read.
    bad.write_text(with_row(4, 2, ""))
    run_cli("curves", clip, "-o", str(tmp_path / "x.csv"), "--timing-from", str(bad), *flags)
    for command, input_clip, extra, message in [
            ("curves", CURVES, ("--timing-fps", "24"),
             "a drawing sheet CSV has a row per output frame and this answer is timed on the "
             "24 fps grid"),
            ("lipblink", LIPBLINK, ("--timing-fps", "0"),
             "a drawing sheet CSV (koma curves --timing: a drawing column); this command reads "
             "only an XDTS sheet (--xdts)"),
            ("skeletal", "samples/pitch.bvh", (),
             "a drawing sheet CSV (koma curves --timing: a drawing column); koma skeletal "
             "reads its timing CSV (--timing) or an XDTS (--xdts)")]:
        out = tmp_path / ("x.bvh" if command == "skeletal" else "x.motion3.json")
        done = run_cli(command, source_path(input_clip), "-o", str(out), "--timing-from",
                       str(sheet), *extra, "--server", server.address, check=False)
        assert done.returncode != 0 and message in done.stderr, (command, done.stderr)
        py = run_python_cli(command, source_path(input_clip), "-o", str(out), "--timing-from",
                            str(sheet), *extra, "--server", server.address)
        assert py.returncode != 0 and message in py.stderr, (command, py.stderr)
    # skeletal's source frame CSV given to curves.
    skeletal_csv = tmp_path / "skeletal.csv"
    skeletal_csv.write_text("output_frame,source_frame,kind,time_s\n0,0,key,0\n")
    done = run_cli("curves", clip, "-o", str(tmp_path / "x.csv"), "--timing-from",
                   str(skeletal_csv), *flags, check=False)
    assert done.returncode != 0 and ("a source frame timing CSV (koma skeletal --timing: no "
                                     "drawing column); koma curves reads its drawing sheet") \
        in done.stderr, done.stderr


def test_batch_curves_and_lipblink_apply_one_sheet_or_each_clips_own(server, tmp_path):
    """koma batch curves|lipblink --timing-from SHEET (every clip) or FOLDER (each clip's
    NAME.xdts or NAME.timing.csv): each clip's output is the bytes `koma curves|lipblink IN
    --timing-from` writes with that clip's sheet (those are checked frame by frame above);
    a rerun is up to date until a sheet is edited; a clip without a sheet is an error."""
    flags = ("--timing-fps", "0", "--server", server.address)
    clips = tmp_path / "clips"
    clips.mkdir()
    for name in ("arm", "arm_copy"):
        (clips / f"{name}.motion3.json").write_bytes(open(source_path(CURVES), "rb").read())
    _, [(track, rows)], _ = written(tmp_path, server, "curves", source_path(CURVES), *flags[:2])
    sheets = tmp_path / "sheets"
    sheets.mkdir()
    (sheets / "arm.xdts").write_text(koma_sheet(EDITS["all four"](rows), track))
    timing = tmp_path / "timing.csv"
    run_cli("curves", source_path(CURVES), "-o", str(tmp_path / "x.csv"), "--timing",
            str(timing), *flags)
    header, csv_body = drawing_sheet(timing)
    (sheets / "arm_copy.timing.csv").write_text(
        spreadsheet_edit(header, csv_body, swap_drawings([int(r[1]) for r in csv_body])),
        newline="")

    def single(clip, sheet):
        out = tmp_path / "single.motion3.json"
        run_cli("curves", str(clip), "-o", str(out), "--timing-from", str(sheet), *flags)
        return out.read_bytes()

    out = tmp_path / "one"
    run_cli("batch", "curves", str(clips), "-o", str(out), "--timing-from",
            str(sheets / "arm.xdts"), *flags)
    for name in ("arm", "arm_copy"):
        assert (out / f"{name}.motion3.json").read_bytes() == \
            single(clips / f"{name}.motion3.json", sheets / "arm.xdts"), name
    out = tmp_path / "each"
    run_cli("batch", "curves", str(clips), "-o", str(out), "--timing-from", str(sheets), *flags)
    assert (out / "arm.motion3.json").read_bytes() == \
        single(clips / "arm.motion3.json", sheets / "arm.xdts")
    assert (out / "arm_copy.motion3.json").read_bytes() == \
        single(clips / "arm_copy.motion3.json", sheets / "arm_copy.timing.csv")
    assert (out / "arm.motion3.json").read_bytes() != (out / "arm_copy.motion3.json").read_bytes()
    rerun = run_cli("batch", "curves", str(clips), "-o", str(out), "--timing-from", str(sheets),
                    *flags)
    assert "0 done, 2 up to date" in rerun.stderr + rerun.stdout
    (sheets / "arm.xdts").write_text(koma_sheet(EDITS["two drawings swapped"](rows), track))
    rerun = run_cli("batch", "curves", str(clips), "-o", str(out), "--timing-from", str(sheets),
                    *flags)
    assert "2 done, 0 up to date" in rerun.stderr + rerun.stdout
    assert (out / "arm.motion3.json").read_bytes() == \
        single(clips / "arm.motion3.json", sheets / "arm.xdts")
    (sheets / "arm_copy.timing.csv").unlink()
    done = run_cli("batch", "curves", str(clips), "-o", str(tmp_path / "none"), "--timing-from",
                   str(sheets), *flags, check=False)
    assert done.returncode == 1 and f"no sheet for {clips / 'arm_copy.motion3.json'}" in \
        done.stderr, done.stderr
    # A sheet that does not fit fails its clip with the single command's message.
    (sheets / "arm_copy.xdts").write_text(koma_sheet([99] + rows[1:], track))
    done = run_cli("batch", "curves", str(clips), "-o", str(tmp_path / "bad"), "--timing-from",
                   str(sheets), *flags, check=False)
    assert done.returncode == 1 and f'track "{track}", frame 1: cell "100" names no drawing' \
        in done.stderr, done.stderr

    # lipblink: the mouth edited, one sheet for the clip.
    lip_clips = tmp_path / "lip_clips"
    lip_clips.mkdir()
    (lip_clips / "talk.motion3.json").write_bytes(open(source_path(LIPBLINK), "rb").read())
    _, tracks, _ = written(tmp_path, server, "lipblink", source_path(LIPBLINK), *flags[:2])
    lip_sheet = tmp_path / "talk_edit.xdts"
    lip_sheet.write_text(two_track_sheet(tracks, [swap_drawings(tracks[0][1]), tracks[1][1]]))
    out = tmp_path / "lip"
    run_cli("batch", "lipblink", str(lip_clips), "-o", str(out), "--timing-from", str(lip_sheet),
            *flags)
    alone, unedited = tmp_path / "talk_alone.motion3.json", tmp_path / "talk.motion3.json"
    run_cli("lipblink", str(lip_clips / "talk.motion3.json"), "-o", str(alone), "--timing-from",
            str(lip_sheet), *flags)
    run_cli("lipblink", str(lip_clips / "talk.motion3.json"), "-o", str(unedited), *flags)
    assert (out / "talk.motion3.json").read_bytes() == alone.read_bytes()
    assert alone.read_bytes() != unedited.read_bytes()
    done = run_cli("batch", "lipblink", str(lip_clips), "-o", str(tmp_path / "v"),
                   "--audio-beside", "--timing-from", str(lip_sheet), *flags, check=False)
    assert done.returncode == 2 and "--timing-from: not with a voice" in done.stderr

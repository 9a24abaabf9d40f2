"""An edited sheet read back (`timing_from=`): the rules of the C++ client, ported
(formats/sheet_timing.cc, client/timing_from.cc; docs/usage.md, "Timing from a sheet"), with
the same messages. tests/python/test_timing_from.py compares the two on the same sheets.

A sheet is {"kind": "xdts"|"source_frames"|"drawings", "rows": int, "tracks": [(name,
[cell, ...])], "warnings": [str]}, a cell the XDTS cell id ("" blank), from skeletal's --timing
CSV source_frame + 1, from curves' drawing sheet CSV drawing + 1 (with "stated": per track
[(line, source_frame text)] per row).
"""
import json
import os

from koma import _xdts

_NULL, _HYPHEN = "SYMBOL_NULL_CELL", "SYMBOL_HYPHEN"
_REPEATS = ("SYMBOL_HYPHEN", "SYMBOL_TICK_1", "SYMBOL_TICK_2")
_MAX_ROWS = 1 << 24
_MAX_TRACKS = 4096
_MAX_QUOTED = 40


def quote(text):
    """formats::QuoteForError: C-escaped in double quotes, cut to 40 bytes."""
    data = text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text
    cut = len(data) > _MAX_QUOTED
    out = []
    for b in data[:_MAX_QUOTED]:
        c = chr(b)
        if c == "\n":
            out.append("\\n")
        elif c == "\r":
            out.append("\\r")
        elif c == "\t":
            out.append("\\t")
        elif c in "\"'\\":
            out.append("\\" + c)
        elif b < 0x20 or b >= 0x7f:
            out.append("\\%03o" % b)
        else:
            out.append(c)
    return '"' + "".join(out) + '"' + ("..." if cut else "")


class SheetError(ValueError):
    """A sheet that does not fit: the message names the file, track, frame and cell."""


def _whole(value, path, lo, hi):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            (isinstance(value, float) and value != int(value)):
        raise SheetError(f"{path}: expected a whole number, got {json.dumps(value)}")
    if value < lo:
        raise SheetError(f"{path}: {json.dumps(value)} must be >= {lo}")
    if value > hi:
        raise SheetError(f"{path}: {json.dumps(value)} must be <= {hi}")
    return int(value)


def _member(obj, path, name, kind=None):
    if not isinstance(obj, dict):
        raise SheetError(f"{path}: expected an object" if path else "expected an object")
    if name not in obj:
        raise SheetError(f"{path}: missing \"{name}\"" if path else f"missing \"{name}\"")
    value = obj[name]
    if kind is list and not isinstance(value, list):
        raise SheetError(f"{path + '.' if path else ''}{name}: expected an array, got "
                         f"{json.dumps(value)}")
    return value


def _expand(entries, duration):
    """OpenToonz's column fill (formats/xdts_reader.cc, ExpandCells)."""
    cells = []
    for frame, value in entries:
        if frame >= duration:
            break
        previous = cells[-1] if cells else ""
        while len(cells) < frame:
            cells.append(previous)
        cell = "" if value == _NULL else (cells[-1] if cells else "") if value in _REPEATS \
            else value
        if len(cells) == frame:
            cells.append(cell)
        else:
            cells[-1] = cell
    last = cells[-1] if cells else ""
    while len(cells) < duration:
        cells.append(last)
    return cells


def read_xdts(data):
    """The Cell tracks of the first time table, by OpenToonz's import rules."""
    text = data.decode("utf-8", "replace") if isinstance(data, bytes) else data
    if text.startswith("\ufeff"):
        text = text[1:]
    first, _, body = text.partition("\n")
    if first.endswith("\r"):
        first = first[:-1]
    if first != _xdts.IDENTIFIER:
        raise SheetError(f"line 1: expected \"{_xdts.IDENTIFIER}\" (an XDTS file), got "
                         f"{quote(first)}")
    try:
        document = json.loads(body)
    except ValueError as error:
        raise SheetError(f"line 2 on: invalid JSON: {error}") from None
    version = _member(document, "", "version")
    if version != 5 or isinstance(version, bool):
        raise SheetError(f"version: {json.dumps(version)} is not 5 (the XDTS version koma reads)")
    tables = _member(document, "", "timeTables", list)
    if not tables:
        raise SheetError("timeTables: expected at least one time table")
    table, at = tables[0], "timeTables[0]"
    duration = _whole(_member(table, at, "duration"), at + ".duration", 1, _MAX_ROWS)
    name = table.get("name", "") if isinstance(table, dict) else ""
    names = []
    headers = _member(table, at, "timeTableHeaders", list)
    for h, header in enumerate(headers):
        header_at = f"{at}.timeTableHeaders[{h}]"
        field_id = _whole(_member(header, header_at, "fieldId"), header_at + ".fieldId", 0,
                          1 << 20)
        header_names = _member(header, header_at, "names", list)
        if field_id == 0:
            names = list(header_names)
    tracks = []
    for f, field in enumerate(table.get("fields", [])):
        field_at = f"{at}.fields[{f}]"
        field_id = _whole(_member(field, field_at, "fieldId"), field_at + ".fieldId", 0, 1 << 20)
        if field_id != 0:
            continue
        field_tracks = _member(field, field_at, "tracks", list)
        if len(field_tracks) > _MAX_TRACKS:
            raise SheetError(f"{field_at}.tracks: {len(field_tracks)} tracks is over the limit "
                             f"of {_MAX_TRACKS}")
        for t, track in enumerate(field_tracks):
            track_at = f"{field_at}.tracks[{t}]"
            number = _whole(_member(track, track_at, "trackNo"), track_at + ".trackNo", 0,
                            _MAX_TRACKS - 1)
            entries = []
            for i, item in enumerate(_member(track, track_at, "frames", list)):
                item_at = f"{track_at}.frames[{i}]"
                frame = _whole(_member(item, item_at, "frame"), item_at + ".frame", 0, _MAX_ROWS)
                instructions = _member(item, item_at, "data", list)
                if not instructions:
                    raise SheetError(f"{item_at}.data: expected at least one instruction")
                values = _member(instructions[0], item_at + ".data[0]", "values", list)
                if not values:
                    raise SheetError(f"{item_at}.data[0].values: expected at least one value")
                if not isinstance(values[0], str):
                    raise SheetError(f"{item_at}.data[0].values[0]: expected a string, got "
                                     f"{json.dumps(values[0])}")
                entries.append((frame, values[0]))
            entries.sort(key=lambda e: e[0])  # stable: a file's order among equal frames
            track_name = names[number] if number < len(names) else ""
            tracks.append((track_name, _expand(entries, duration)))
    warnings = []
    if len(tables) > 1:
        extra = len(tables) - 1
        warnings.append(f"{extra} extra time table{'' if extra == 1 else 's'} ignored: koma "
                        f"reads the first ({quote(name)})")
    return {"kind": "xdts", "rows": duration, "tracks": tracks, "warnings": warnings}


def _csv_count(value, line, column):
    if not value or len(value) > 9 or not value.isdigit() or not value.isascii():
        raise SheetError(f"line {line}: {column} {quote(value)} is not a whole number >= 0")
    return int(value)


def _blank_line(line):
    return all(c in " \t\r," for c in line)


def read_csv(data, max_rows=_MAX_ROWS):
    """koma's --timing CSV, edited in a spreadsheet (formats::ReadSheetTimingCsv)."""
    text = data.decode("utf-8", "replace") if isinstance(data, bytes) else data
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    first = 0
    while first < len(lines) and _blank_line(lines[first]):
        first += 1
    if first == len(lines):
        raise SheetError("no header line: the file is empty")

    def values_of(line):
        line = line[:-1] if line.endswith("\r") else line
        values = [v.strip(" \t\n\v\f\r") for v in line.split(",")]
        # A spreadsheet may quote a cell: read without its quotes, "" inside as one.
        return [v[1:-1].replace('""', '"') if len(v) >= 2 and v[0] == v[-1] == '"' else v
                for v in values]

    header = values_of(lines[first])
    if "drawing" in header:
        return _read_drawing_csv(lines, first, header, values_of, max_rows)
    source_column = grid_column = -1
    for c, name in enumerate(header):
        if name == "source_frame":
            source_column = c
        if name == "grid_frame":
            grid_column = c
    if source_column < 0:
        raise SheetError(f"line {first + 1}: no source_frame column in the header "
                         f"{quote(lines[first])} (koma's --timing sheet: "
                         "output_frame,source_frame,kind,time_s[,grid_frame])")
    cells, previous_grid = [], -1
    for index in range(first + 1, len(lines)):
        if _blank_line(lines[index]):
            continue
        line = index + 1
        values = values_of(lines[index])

        def value(column):
            return values[column] if column < len(values) else ""

        cell = ""
        if value(source_column):
            cell = str(_csv_count(value(source_column), line, "source_frame") + 1)
        if grid_column < 0:
            if len(cells) >= max_rows:
                raise SheetError(f"line {line}: more than {max_rows} rows")
            cells.append(cell)
            continue
        grid = _csv_count(value(grid_column), line, "grid_frame")
        if grid >= max_rows:
            raise SheetError(f"line {line}: grid_frame {grid} must be < {max_rows}")
        if grid < previous_grid:
            raise SheetError(f"line {line}: grid_frame {grid} comes after grid_frame "
                             f"{previous_grid} (grid frames must not decrease)")
        if grid == previous_grid:
            if not cells[-1]:
                cells[-1] = cell
            if cell and cell != cells[-1]:
                raise SheetError(f"line {line}: grid_frame {grid} shows source_frame "
                                 f"{value(source_column)} here and a different one on a line "
                                 "before (one grid frame shows one drawing)")
            continue
        before = cells[-1] if cells else ""
        while len(cells) < grid:
            cells.append(before)
        cells.append(cell)
        previous_grid = grid
    if not cells:
        raise SheetError(f"no rows after the header on line {first + 1}")
    return {"kind": "source_frames", "rows": len(cells), "tracks": [("", cells)],
            "warnings": []}


def _read_drawing_csv(lines, first, header, values_of, max_rows):
    """formats::ReadDrawingSheetCsv: `koma curves --timing`'s drawing sheet; per track also
    "stated": [(line, source_frame text)] per row."""
    columns, tracks, stated = [], [], []
    for c, name in enumerate(header):
        if name == "drawing" or (len(name) > len("_drawing") and name.endswith("_drawing")):
            group = "" if name == "drawing" else name[:-len("_drawing")]
            source_name = f"{group}_source_frame" if group else "source_frame"
            source = -1
            for s, other in enumerate(header):
                if other == source_name:
                    source = s
            columns.append((c, source))
            tracks.append((name, []))
            stated.append([])
    rows = 0
    for index in range(first + 1, len(lines)):
        if _blank_line(lines[index]):
            continue
        line = index + 1
        if rows >= max_rows:
            raise SheetError(f"line {line}: more than {max_rows} rows")
        values = values_of(lines[index])

        def value(column):
            return values[column] if 0 <= column < len(values) else ""

        for k, (drawing_column, source_column) in enumerate(columns):
            cell = ""
            if value(drawing_column):
                cell = str(_csv_count(value(drawing_column), line, header[drawing_column]) + 1)
            tracks[k][1].append(cell)
            stated[k].append((line, value(source_column)))
        rows += 1
    if rows == 0:
        raise SheetError(f"no rows after the header on line {first + 1}")
    return {"kind": "drawings", "rows": rows, "tracks": tracks, "stated": stated,
            "warnings": []}


def match_tracks(sheet, koma_tracks):
    """formats::MatchSheetTracks: by name, then by order."""
    tracks = sheet["tracks"]
    match, taken = [-1] * len(koma_tracks), [False] * len(tracks)
    for k, name in enumerate(koma_tracks):
        for s, (sheet_name, _) in enumerate(tracks):
            if not taken[s] and sheet_name == name:
                match[k], taken[s] = s, True
                break
    following = 0
    for k, name in enumerate(koma_tracks):
        if match[k] >= 0:
            continue
        while following < len(taken) and taken[following]:
            following += 1
        if following == len(taken):
            are = "is" if len(tracks) == 1 else "s are"
            raise SheetError(f"no track for {quote(name)}: the sheet's {len(tracks)} Cell "
                             f"track{are} taken by the clip's other tracks (tracks match by "
                             "name, then by order)")
        match[k], taken[following] = following, True
    for s, was_taken in enumerate(taken):
        if not was_taken:
            names = ", ".join(quote(n) for n in koma_tracks)
            raise SheetError(f"track {quote(tracks[s][0])} (Cell track {s + 1} of {len(tracks)}): "
                             f"no such track: the clip's tracks are {names}")
    return match


def drawings(name, cells, drawing_count, what):
    """formats::SheetDrawings: cell n is drawing n - 1; a blank holds the drawing before."""
    out, first = [-1] * len(cells), -1
    for row, cell in enumerate(cells):
        if not cell:
            if row > 0:
                out[row] = out[row - 1]
            continue
        ok = len(cell) <= 9 and cell.isdigit() and cell.isascii() and \
            1 <= int(cell) <= drawing_count
        if not ok:
            raise SheetError(f"track {quote(name)}, frame {row + 1}: cell {quote(cell)} names "
                             f"no drawing (cells are {what})")
        out[row] = int(cell) - 1
        if first < 0:
            first = int(cell) - 1
    if first < 0:
        raise SheetError(f"track {quote(name)}: every one of its {len(cells)} frames is blank "
                         "(no drawing to show)")
    for row in range(len(out)):
        if out[row] >= 0:
            break
        out[row] = first
    return out


def read(path):
    """client::ReadTimingFrom: XDTS by its first line or .xdts name, else the CSV."""
    with open(path, "rb") as f:
        data = f.read()
    start = data[3:] if data.startswith(b"\xef\xbb\xbf") else data
    try:
        if start.startswith(_xdts.IDENTIFIER.encode()) or str(path).lower().endswith(".xdts"):
            sheet = read_xdts(data)
        else:
            sheet = read_csv(data)
    except SheetError as error:
        raise SheetError(f"{os.fspath(path)}: {error}") from None
    sheet["warnings"] = [f"{os.fspath(path)}: {w}" for w in sheet["warnings"]]
    return sheet


def skeletal_source_frames(path, track, frame_count, source_fps, timing_fps):
    """client::SetSkeletalTimingFrom: (given_timing.source_frames, warnings). frame_count 0:
    the clip's length is unknown here (a file the server reads whole; it checks)."""
    if frame_count > 0:
        count, what = frame_count, f"the clip's source frames 1 to {frame_count}"
    else:
        count, what = 1 << 30, "source frames from 1"
    counted, note = 0, ""
    if frame_count > 0:
        fps = 24.0 if timing_fps is None else timing_fps
        grid = _xdts._FilmGrid.make(source_fps, fps)
        counted = grid.grid_frame_count(frame_count) if grid else frame_count
        note = f" on the {_number(fps)} fps grid" if grid else ""
    shown, warnings = read_drawings(path, [(track, count, what)], counted, True, note)
    return shown[0], warnings


def _float(text):
    """absl::SimpleAtod: a decimal or exponent number (inf/nan too), else None."""
    try:
        return float(text)
    except ValueError:
        return None


def _number(value):
    """absl::StrCat of a double: %g with 6 significant digits."""
    return "%g" % value


_CSV_RULES = {
    "xdts": "; this command reads only an XDTS sheet (--xdts)",
    "drawings": "; koma curves reads its drawing sheet (--timing) or an XDTS (--xdts)",
    "source_frames": "; koma skeletal reads its timing CSV (--timing) or an XDTS (--xdts)",
}

# client::kStatedTauTolerance: source frames a drawing sheet row's source_frame may be off.
_STATED_TAU_TOLERANCE = 0.01


def read_drawings(path, koma_tracks, counted, shorter_ok, counted_note, csv="source_frames"):
    """client::ReadSheetDrawings: koma_tracks is [(name, drawing count, what[, column in a
    drawing sheet CSV, taus])]; csv the CSV kind this command reads ("xdts": none); returns
    (per track the 0-based drawing per row, warnings)."""
    sheet = read(path)
    where = os.fspath(path)
    if sheet["kind"] != "xdts" and sheet["kind"] != csv:
        what = ("a drawing sheet CSV (koma curves --timing: a drawing column)"
                if sheet["kind"] == "drawings"
                else "a source frame timing CSV (koma skeletal --timing: no drawing column)")
        raise SheetError(f"{where}: {what}{_CSV_RULES[csv]}")
    drawing_csv = sheet["kind"] == "drawings"
    if drawing_csv and counted_note:
        raise SheetError(f"{where}: a drawing sheet CSV has a row per output frame and this "
                         f"answer is timed{counted_note}: apply the XDTS (--xdts) instead, or "
                         "write and apply the CSV with --timing-fps 0")
    out = []
    try:
        names = [t[3] if drawing_csv else t[0] for t in koma_tracks]
        match = match_tracks(sheet, names)
        for koma_track, index in zip(koma_tracks, match):
            count, what = koma_track[1], koma_track[2]
            name, cells = sheet["tracks"][index]
            for r, cell in enumerate(cells if drawing_csv else []):
                # A drawing sheet names drawings from 0 (its cells are drawing + 1).
                if cell and int(cell) > count:
                    raise SheetError(f"line {sheet['stated'][index][r][0]}: track {quote(name)}, "
                                     f"frame {r + 1}: drawing {int(cell) - 1} names no drawing "
                                     f"(the drawings are 0 to {count - 1})")
            shown = drawings(name, cells, count, what)
            rows = len(shown)
            if counted > 0 and (rows > counted or (rows < counted and not shorter_ok)):
                if rows > counted:
                    at = (f", frame {counted + 1}: cell {quote(cells[counted])} is past the "
                          "clip's end")
                else:
                    at = f", frame {rows}: the sheet ends before the clip"
                rule = ("(a sheet may be shorter, not longer)" if shorter_ok
                        else "(a sheet has every frame)")
                raise SheetError(f"track {quote(name)}{at}: the sheet has {rows} frames, the "
                                 f"clip {counted}{counted_note} {rule}")
            taus = koma_track[4] if len(koma_track) > 4 else []
            for r, (line, stated) in enumerate(sheet.get("stated", [[]] * len(match))[index]):
                if not stated or not taus:
                    continue
                tau = taus[shown[r]]
                value = _float(stated)
                if value is None or not abs(value - tau) <= _STATED_TAU_TOLERANCE:
                    raise SheetError(
                        f"line {line}: track {quote(name)}, frame {r + 1}: drawing {shown[r]} "
                        f"is source frame {_number(tau)}, the row's source_frame says "
                        f"{quote(stated)} (koma reads the drawing column: change the drawing, "
                        "or clear source_frame)")
            out.append(shown)
    except SheetError as error:
        raise SheetError(f"{where}: {error}") from None
    return out, sheet["warnings"]


def _grid_note(timing_fps):
    return f" on the {_number(timing_fps)} fps grid" if timing_fps > 0 else ""


def curves_given_timings(path, name, computed, request):
    """client::SetCurvesTimingFrom: request.given_timings from the sheet, read against
    koma's own answer `computed`; returns the warnings."""
    sheet = _xdts.curves_sheet(computed, name)
    timing_of_track = [t for t in range(len(computed.timings))
                       if any(c.timing == t for c in computed.curves)]
    tracks, groups = [], []
    for k, t in enumerate(timing_of_track):
        track = sheet["cells"][k][0]
        group = next((g.name for g in computed.timing_groups if g.timing == t), None)
        if group is None and not computed.timing_groups and t == 0:
            group = "body"
        if group is None:
            raise SheetError(f"{os.fspath(path)}: track {quote(track)}: the timing of "
                             "--curve-on curves cannot be given, only a timing group's own")
        groups.append(group)
        count = len(computed.timings[t].drawing_source_frame)
        # The drawing sheet CSV's columns: `drawing` for its first group (groups with
        # drawings, in order), `G_drawing` for a further group G.
        first_csv = next((g.timing for g in computed.timing_groups
                          if len(g.curves) > 0 and g.frames_per_drawing != 0), 0)
        column = "drawing" if t == first_csv else f"{group}_drawing"
        tracks.append((track, count, f"its drawings 1 to {count}", column,
                       list(computed.timings[t].drawing_source_frame)))
    shown, warnings = read_drawings(path, tracks, sheet["duration"], False,
                                    _grid_note(computed.timing_fps), "drawings")
    for k, t in enumerate(timing_of_track):
        timing = computed.timings[t]
        given = request.given_timings.add(group=groups[k])
        unedited = [int(cell) - 1 for cell in sheet["cells"][k][1]]
        # An edited track shows each drawing at its tau exactly (as the C++ client).
        given.exact_taus = shown[k] != unedited
        given.source_frame.extend(timing.drawing_source_frame[d] for d in shown[k])
    return warnings


_MOUTH_LEGEND = " (1 closed, 2 mid, 3 open)"
_EYE_LEGEND = " (1 open, 2 half, 3 closed)"


def _mouth_from_cells(mouth, cells, unedited, given):
    """client's MouthFromCells: holds over koma's speech and the changed rows."""
    rows = len(cells)
    held = [False] * rows
    for speech in mouth.speech:
        for r in range(max(speech.begin, 0), min(speech.end, rows)):
            held[r] = True
    held = [h or cells[r] != unedited[r] for r, h in enumerate(held)]
    r = 0
    while r < rows:
        if not held[r]:
            r += 1
            continue
        end = r
        while end < rows and held[end] and cells[end] == cells[r]:
            end += 1
        # Cells 1, 2, 3 are MOUTH_CLOSED, MOUTH_MID, MOUTH_OPEN (1, 2, 3).
        given.holds.add(begin=r, length=end - r, shape=cells[r] + 1)
        r = end


def _blink_of_run(cells, begin, end, track):
    closed_end = begin
    while closed_end < end and cells[closed_end] == 2:
        closed_end += 1
    half_end = closed_end
    while half_end < end and cells[half_end] == 1:
        half_end += 1
    closed, half = closed_end - begin, half_end - closed_end
    if closed == 0 or half_end != end or not 1 <= half <= 3 or half > closed:
        shown = "".join(str(c + 1) for c in cells[begin:end])
        raise SheetError(f"track {quote(track)}, frame {begin + 1}: cells {shown} are no blink "
                         "koma paints: a blink is closed (3) for c frames, then half (2) for 1 "
                         "to 3 frames, at most c, then open (1)")
    return {"closing_begin": begin, "closed_begin": begin, "closed_end": closed_end - 1,
            "hold": half, "open_span": 0}


def _eye_from_cells(eye, cells, unedited, track, given):
    """client's EyeFromCells: koma's blinks where unchanged, else runs of non-open cells."""
    rows = len(cells)
    painted = _xdts._blink_rows(eye, rows)
    kept = [False] * rows
    blinks = []
    for i, blink in enumerate(eye.blinks):
        limit = eye.blinks[i + 1].closing_begin if i + 1 < len(eye.blinks) else rows
        end = max(blink.closed_begin, 0)
        while end < min(limit, rows) and painted[end] >= 0:
            end += 1
        begin = max(blink.closing_begin, 0)
        if cells[begin:end] != unedited[begin:end]:
            continue
        for r in range(begin, end):
            kept[r] = True
        blinks.append({f.name: getattr(blink, f.name) for f in blink.DESCRIPTOR.fields})
    r = 0
    while r < rows:
        if cells[r] == 0 or kept[r]:
            r += 1
            continue
        end = r
        while end < rows and cells[end] != 0 and not kept[end]:
            end += 1
        blink = _blink_of_run(cells, r, end, track)
        before = r
        while before > 0 and cells[before - 1] == 0 and painted[before - 1] >= 0 \
                and not kept[before - 1]:
            before -= 1
        after = end
        while after < rows and cells[after] == 0 and painted[after] >= 0 and not kept[after]:
            after += 1
        blink["closing_begin"] = before
        blink["open_span"] = max(0, after - 1 - blink["closed_end"])
        blinks.append(blink)
        r = end
    for blink in sorted(blinks, key=lambda b: b["closed_begin"]):
        given.blinks.add(**blink)


def lip_blink_given_timing(path, name, source_fps, computed, request):
    """client::SetLipBlinkTimingFrom: request.given_timing from the sheet, read against koma's
    own answer `computed`; returns the warnings."""
    sheet = _xdts.lip_blink_sheet(computed, source_fps, name)
    tracks = [(track, 3, "1 to 3") for track, _ in sheet["cells"]]
    shown, warnings = read_drawings(path, tracks, sheet["duration"], False,
                                    _grid_note(computed.timing_fps), "xdts")
    for k, (track, written) in enumerate(sheet["cells"]):
        cells, unedited = shown[k], [int(cell) - 1 for cell in written]
        mouth = track.endswith(_MOUTH_LEGEND)
        ids = track[:-len(_MOUTH_LEGEND if mouth else _EYE_LEGEND)].split(", ")
        for curve_id in ids:
            if mouth:
                for m in computed.mouths:
                    if m.id == curve_id:
                        _mouth_from_cells(m, cells, unedited,
                                          request.given_timing.mouths.add(id=curve_id))
                continue
            for e in computed.eyes:
                if e.id == curve_id:
                    try:
                        _eye_from_cells(e, cells, unedited, track,
                                        request.given_timing.eyes.add(id=curve_id))
                    except SheetError as error:
                        raise SheetError(f"{os.fspath(path)}: {error}") from None
    return warnings

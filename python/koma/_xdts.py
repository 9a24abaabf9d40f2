"""XDTS exposure sheets of the three answers, byte for byte what `koma ... --xdts` writes.

The same rules as the C++ client (client/xdts_sheets.cc, formats/xdts_writer.cc), ported:
docs/formats.md ("XDTS exposure sheet") has the mapping. tests/e2e/xdts_e2e_test.sh compares
the two on every sample.
"""
import json
import math
import os

from koma import _format_table

IDENTIFIER = "exchangeDigitalTimeSheet Save Data"
NULL_CELL = "SYMBOL_NULL_CELL"
HYPHEN = "SYMBOL_HYPHEN"

# core/film_grid.cc's constants.
_SAME_RATE_TOLERANCE = 1e-4
_MIN_SOURCE_FPS, _MAX_SOURCE_FPS = 1e-3, 1e6
_MAX_DENOMINATOR = 100000
_MAX_UPSAMPLING = 1000000000
_MAX_NUMERATOR = 1 << 30


class _FilmGrid:
    """core/film_grid.h: source frames per grid frame = p / q, integer mappings."""

    def __init__(self, p, q):
        self.p, self.q = p, q

    @staticmethod
    def make(source_fps, timing_fps):
        if not timing_fps > 0 or not _MIN_SOURCE_FPS <= source_fps <= _MAX_SOURCE_FPS:
            return None
        if abs(source_fps - timing_fps) <= _SAME_RATE_TOLERANCE * timing_fps:
            return None
        ratio = source_fps / timing_fps
        if ratio >= float(_MAX_NUMERATOR):
            return _FilmGrid(_MAX_NUMERATOR, 1)
        p0, q0 = 1, 0
        p1, q1 = int(math.floor(ratio)), 1
        rest = ratio - math.floor(ratio)
        while abs(float(p1) / float(q1) - ratio) > _SAME_RATE_TOLERANCE * ratio and rest > 0:
            inverse = 1.0 / rest
            if math.floor(inverse) * float(q1) > float(_MAX_DENOMINATOR):
                break
            a = int(math.floor(inverse))
            p2, q2 = a * p1 + p0, a * q1 + q0
            if q2 > _MAX_DENOMINATOR:
                break
            p0, q0, p1, q1 = p1, q1, p2, q2
            rest = inverse - math.floor(inverse)
        if p1 == 0:
            p1 = 1
            q1 = _MAX_UPSAMPLING if 1.0 / ratio >= float(_MAX_UPSAMPLING) else \
                int(math.floor(1.0 / ratio + 0.5))
        return _FilmGrid(p1, q1)

    def grid_frame_of(self, k):
        return (k * self.q) // self.p

    def grid_frame_count(self, source_frames):
        return 0 if source_frames < 1 else self.grid_frame_of(source_frames - 1) + 1

    def nearest_source_frame(self, g, last):
        k = -((-(2 * g * self.p - self.q)) // (2 * self.q))  # ceil; an exact half goes down
        return max(0, min(last, k))


def clip_name(source_path, fallback):
    """client/xdts_sheets.cc XdtsClipName: the file name without folder and extension."""
    for path in (source_path, fallback):
        if not path or path == "-":
            continue
        base = os.fspath(path).rsplit("/", 1)[-1]
        # An input format's extension (the format table), else a sheet's own.
        extension = _format_table.extension_length(base)
        for sheet in (".xdts", ".tsv"):
            if not extension and len(base) > len(sheet) and base.lower().endswith(sheet):
                extension = len(sheet)
        base = base[:len(base) - extension]
        if base:
            return base
    return "koma"


def skeletal_sheet(response, name):
    frames = len(response.source_frames)
    if frames == 0:
        raise ValueError("the answer has no output frames")
    if response.timing_fps > 0 and len(response.grid_frames) == frames:
        shown = [-1] * (max(response.grid_frames) + 1)
        for t in range(frames):
            g = response.grid_frames[t]
            if shown[g] < 0:
                shown[g] = response.source_frames[t]
        for r in range(1, len(shown)):
            if shown[r] < 0:
                shown[r] = shown[r - 1]
    else:
        shown = list(response.source_frames)
    # Cells named after the source frame they show, from 1 (what --timing-from reads back).
    return {"name": name, "duration": len(shown), "cells": [(name, [str(s + 1) for s in shown])],
            "dialog": []}


def _curves_track_name(response, t, ids, only):
    """client/xdts_sheets.cc CurvesTrackName: the group's name, else `only`, else the ids."""
    for group in response.timing_groups:
        for c in group.curves:
            if not 0 <= c < len(response.curves) or response.curves[c].timing != t:
                continue
            if group.timing == t:
                return group.name
            return f"{group.name}: {', '.join(ids)}"
    return only or ", ".join(ids)


def curves_sheet(response, name):
    ids = [[] for _ in response.timings]
    for curve in response.curves:
        if 0 <= curve.timing < len(response.timings):
            ids[curve.timing].append(curve.id)
    grid = response.timing_fps > 0
    rows = 0
    for i, timing in enumerate(response.timings):
        if not ids[i]:
            continue
        if grid:
            length = timing.drawing_start_grid[-1] + 1 if timing.drawing_start_grid else 0
        else:
            length = len(timing.drawing_of_frame)
        rows = max(rows, length)
    if rows == 0:
        raise ValueError("the answer times no curve")
    tracks = sum(1 for group in ids if group)
    cells, dialog = [], []
    for i, timing in enumerate(response.timings):
        if not ids[i]:
            continue
        track_name = (f"{_curves_track_name(response, i, ids[i], name if tracks == 1 else '')}"
                      f" (on {timing.frames_per_drawing})")
        column = []
        starts = list(timing.drawing_start_grid)
        of_frame = timing.drawing_of_frame
        d = 0
        for r in range(rows):
            if grid:
                while d < len(starts) and starts[d] <= r:
                    d += 1
                drawing = d - 1
            else:
                drawing = of_frame[min(r, len(of_frame) - 1)]
            column.append(str(max(drawing, 0) + 1))
        cells.append((track_name, column))
        # client/xdts_sheets.cc: a one-row line where each drawing that draws a key starts.
        keys = [[] for _ in timing.drawing_start]
        for curve in response.curves:
            if curve.timing != i:
                continue
            for key in curve.keys:
                if key.drawn and 0 <= key.drawing < len(keys):
                    if not keys[key.drawing] or keys[key.drawing][-1] != curve.id:
                        keys[key.drawing].append(curve.id)
        begins = list(timing.drawing_start_grid) if grid else list(timing.drawing_start)
        lines = [(begins[d], begins[d] + 1, "key", ", ".join(keys[d]))
                 for d in range(min(len(begins), len(keys))) if keys[d] and 0 <= begins[d] < rows]
        if lines:
            dialog.append((f"{track_name} keys", lines))
    return {"name": name, "duration": rows, "cells": cells, "dialog": dialog}


def _nearest_level(value, levels):
    best = 0
    for i in (1, 2):
        d = value - levels[i] if value > levels[i] else levels[i] - value
        b = value - levels[best] if value > levels[best] else levels[best] - value
        if d < b:
            best = i
    return best


def _group_tracks(ids, columns, legend):
    tracks, names = [], []
    for track_id, column in zip(ids, columns):
        for t, (_, existing) in enumerate(tracks):
            if existing == column:
                names[t].append(track_id)
                break
        else:
            tracks.append(("", column))
            names.append([track_id])
    return [(f"{', '.join(names[t])} {legend}", column) for t, (_, column) in enumerate(tracks)]


def _blink_rows(eye, rows):
    out = [-1] * rows

    def fill(begin, end, drawing):
        for r in range(max(begin, 0), min(end, rows)):
            out[r] = drawing

    blinks = list(eye.blinks)
    for i, b in enumerate(blinks):
        limit = blinks[i + 1].closing_begin if i + 1 < len(blinks) else rows
        closed_last = max(b.closed_end, b.closed_begin + b.hold - 1)
        end = min(max(b.closed_end + 1 + b.open_span, closed_last + 1 + b.hold), limit)
        closed_stop = min(end, closed_last + 1)
        mid_stop = min(end, closed_stop + b.hold)
        fill(b.closing_begin, b.closed_begin, 0)
        fill(b.closed_begin, closed_stop, 2)
        fill(closed_stop, mid_stop, 1)
        fill(mid_stop, end, 0)
    return out


def lip_blink_sheet(response, source_fps, name):
    from koma.v1 import retime_pb2
    if not response.curves:
        raise ValueError("the answer has no curves")
    frames = len(response.curves[0].values)
    if frames == 0:
        raise ValueError("the answer's curves have no frames")
    grid = _FilmGrid.make(source_fps, response.timing_fps) if response.timing_fps > 0 else None
    rows = grid.grid_frame_count(frames) if grid else frames
    source_of_row = [grid.nearest_source_frame(r, frames - 1) if grid else r for r in range(rows)]
    curve_of = {c.id: c for c in response.curves}

    def nearest(curve_id, levels):
        curve = curve_of.get(curve_id)
        if curve is None or len(curve.values) != frames:
            return [0] * rows
        values = curve.values
        return [_nearest_level(values[source_of_row[r]], levels) for r in range(rows)]

    shape_index = {retime_pb2.MOUTH_OPEN: 2, retime_pb2.MOUTH_MID: 1}
    mouth_ids, mouth_columns = [], []
    for mouth in response.mouths:
        shape = nearest(mouth.id, (mouth.closed_level, mouth.mid_level, mouth.open_level))
        for hold in mouth.holds:
            value = shape_index.get(hold.shape, 0)
            for r in range(max(hold.begin, 0), min(hold.begin + hold.length, rows)):
                shape[r] = value
        mouth_ids.append(mouth.id)
        mouth_columns.append([str(s + 1) for s in shape])
    cells = _group_tracks(mouth_ids, mouth_columns, "(1 closed, 2 mid, 3 open)")

    eye_ids, eye_columns = [], []
    for eye in response.eyes:
        drawing = nearest(eye.id, (eye.open_level, eye.mid_level, eye.closed_level))
        painted = _blink_rows(eye, rows)
        eye_ids.append(eye.id)
        eye_columns.append([str((p if p >= 0 else d) + 1) for p, d in zip(painted, drawing)])
    cells += _group_tracks(eye_ids, eye_columns, "(1 open, 2 half, 3 closed)")

    speakers, speech_lists = [], []
    for mouth in response.mouths:
        speech = [(max(i.begin, 0), min(i.end, rows)) for i in mouth.speech]
        speech = [(b, e) for b, e in speech if b < e]
        if speech in speech_lists:
            speakers[speech_lists.index(speech)].append(mouth.id)
        else:
            speech_lists.append(speech)
            speakers.append([mouth.id])
    dialog = []
    for t, speech in enumerate(speech_lists):
        lines = [(b, e, name, f"speech {k + 1}") for k, (b, e) in enumerate(speech)]
        dialog.append((f"{', '.join(speakers[t])} speech", lines))
    return {"name": name, "duration": rows, "cells": cells, "dialog": dialog}


def _json_string(text):
    return json.dumps(text, ensure_ascii=False)


def _entry(frame, values, last):
    joined = ", ".join(_json_string(v) for v in values)
    return (f'                {{"data": [{{"id": 0, "values": [{joined}]}}], "frame": {frame}}}'
            + ("\n" if last else ",\n"))


def write(sheet):
    """The XDTS text of a sheet dict (formats/xdts_writer.cc's layout, byte for byte)."""
    duration = sheet["duration"]
    any_dialog = any(lines for _, lines in sheet["dialog"])
    out = [IDENTIFIER, "\n{\n  \"timeTables\": [\n    {\n",
           f'      "duration": {duration},\n      "fields": [\n',
           '        {\n          "fieldId": 0,\n          "tracks": [\n']
    for t, (_, cells) in enumerate(sheet["cells"]):
        out.append('            {\n              "frames": [\n')
        for r, cell in enumerate(cells):
            if r > 0 and cell == cells[r - 1]:
                continue
            out.append(_entry(r, [cell if cell else NULL_CELL], False))
        out.append(_entry(duration, [NULL_CELL], True))
        out.append(f'              ],\n              "trackNo": {t}\n            }}'
                   + ("\n" if t + 1 == len(sheet["cells"]) else ",\n"))
    out.append("          ]\n        }" + (",\n" if any_dialog else "\n"))
    if any_dialog:
        out.append('        {\n          "fieldId": 3,\n          "tracks": [\n')
        with_lines = [t for t, (_, lines) in enumerate(sheet["dialog"]) if lines]
        for t in with_lines:
            lines = sheet["dialog"][t][1]
            out.append('            {\n              "frames": [\n')
            for k, (begin, end, speaker, text) in enumerate(lines):
                for row in range(begin, end):
                    final = k + 1 == len(lines) and row + 1 == end
                    values = [speaker, text] if row == begin else [HYPHEN]
                    out.append(_entry(row, values, final))
            out.append(f'              ],\n              "trackNo": {t}\n            }}'
                       + ("\n" if t == with_lines[-1] else ",\n"))
        out.append("          ]\n        }\n")
    out.append(f'      ],\n      "name": {_json_string(sheet["name"])},\n'
               '      "timeTableHeaders": [\n')
    names = ", ".join(_json_string(n) for n, _ in sheet["cells"])
    out.append(f'        {{"fieldId": 0, "names": [{names}]}}' + ("\n" if not any_dialog else ",\n"))
    if any_dialog:
        names = ", ".join(_json_string(n) for n, _ in sheet["dialog"])
        out.append(f'        {{"fieldId": 3, "names": [{names}]}}\n')
    out.append('      ]\n    }\n  ],\n  "version": 5\n}\n')
    return "".join(out)

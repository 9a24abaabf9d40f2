"""An independent XDTS reader for the tests, following OpenToonz's import
(toonz/sources/toonz/xdtsio.cpp: loadXdtsScene, XdtsFieldTrackItem::getCellFrameIdTrack), and
the JSON Schema written from the published field list (xdts.schema.json).

OpenToonz's rules: the data must start with the identifier "exchangeDigitalTimeSheet Save Data",
which is removed before the JSON is parsed; the first time table is read; a Cell track's
entries are sorted by frame, every frame up to an entry repeats the last cell (empty before
the first), SYMBOL_HYPHEN / SYMBOL_TICK_1 / SYMBOL_TICK_2 repeat the last cell,
SYMBOL_NULL_CELL is empty; after the entries, a last cell that is not empty runs to the end of
the sheet (`duration`); layer names are the Cell header's names by trackNo.
"""
import json
import os

IDENTIFIER = b"exchangeDigitalTimeSheet Save Data"
SCHEMA_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "xdts.schema.json")
REPEAT = ("SYMBOL_HYPHEN", "SYMBOL_TICK_1", "SYMBOL_TICK_2")


def load(data):
    """(the JSON document, its text) of an XDTS file's bytes; AssertionError if malformed."""
    assert data.startswith(IDENTIFIER), "the first line does not start with the XDTS identifier"
    first_line, _, rest = data.partition(b"\n")
    assert first_line == IDENTIFIER, f"first line {first_line!r}"
    text = rest.decode("utf-8")  # strict: invalid UTF-8 fails here
    return json.loads(text), text


def validate(document):
    import jsonschema
    with open(SCHEMA_PATH, encoding="utf-8") as f:
        schema = json.load(f)
    jsonschema.Draft7Validator(schema).validate(document)


def cell_track(track, duration):
    """Per row 0 .. duration - 1 the cell shown (None = empty), OpenToonz's way."""
    entries = sorted(((f["frame"], f["data"][0]["values"][0]) for f in track["frames"]),
                     key=lambda e: e[0])
    cells = []
    initial = None
    for frame, value in entries:
        while len(cells) < frame:
            cells.append(cells[-1] if cells else initial)
        if value == "SYMBOL_NULL_CELL":
            cells.append(None)
        elif value in REPEAT:
            cells.append(cells[-1] if cells else None)
        else:
            cells.append(value)
    last = cells[-1] if cells else None
    if last is not None:
        while len(cells) < duration:
            cells.append(last)
    # The sheet is `duration` rows: OpenToonz sets the scene's range to it.
    cells = cells[:duration]
    while len(cells) < duration:
        cells.append(None)
    return cells


def dialog_lines(track):
    """[(begin, end, values of the first frame)]: a line runs from an entry that is not
    SYMBOL_HYPHEN through the hyphens that follow it, one per frame."""
    lines = []
    for f in sorted(track["frames"], key=lambda f: f["frame"]):
        values = f["data"][0]["values"]
        if values[0] == "SYMBOL_HYPHEN":
            assert lines and lines[-1][1] == f["frame"], f"hyphen at {f['frame']} continues nothing"
            lines[-1][1] = f["frame"] + 1
        else:
            lines.append([f["frame"], f["frame"] + 1, values])
    return [(b, e, v) for b, e, v in lines]


def read(data):
    """{"name", "duration", "cells": [(layer name, cells)], "dialog": [(name, lines)]}."""
    document, _ = load(data)
    table = document["timeTables"][0]
    duration = table["duration"]
    names = {h["fieldId"]: h["names"] for h in table["timeTableHeaders"]}
    out = {"name": table["name"], "duration": duration, "cells": [], "dialog": []}
    for field in table.get("fields", []):
        for track in field["tracks"]:
            name = names.get(field["fieldId"], [])[track["trackNo"]]
            if field["fieldId"] == 0:
                out["cells"].append((name, cell_track(track, duration)))
            elif field["fieldId"] == 3:
                out["dialog"].append((name, dialog_lines(track)))
    return out

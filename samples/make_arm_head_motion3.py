#!/usr/bin/env python3
"""Writes samples/arm_head.motion3.json: a synthetic Live2D Cubism motion for koma's tests.

3 seconds at 30 fps (frames 0-90) of five standard Cubism parameters:

  ParamAngleX      head turn: eases to 25 degrees, holds, swings to -15, settles at 0;
  ParamAngleY      small nod: down to -6, up to 4, back to 0;
  ParamBodyAngleX  the body follows the head, later and smaller (6, then -4);
  ParamArmLA       left arm swings forward and back, then rests (a stepped hold at the end);
  ParamArmRA       right arm swings the other way (an inverse-stepped hold at the start) and
                   has its own FadeInTime/FadeOutTime.

Every key sits on a frame that is a multiple of 9 (0.3 s), so each Bezier's handles sit
exactly at 1/3 and 2/3 of its segment on multiples of 0.1 s, as Cubism Editor places them
when AreBeziersRestricted is true; handle values repeat the neighbouring key's value (ease in
and out). The stepped and inverse-stepped segments join equal values, so they change nothing
visible. Two UserData events mark the head's turns.

Times are exact fractions of a second (fractions.Fraction) turned into the shortest decimal
text, and the JSON is written by the json module with one tab per level, the layout Cubism
Editor uses, so the output is byte-identical on every machine.

Usage: python3 make_arm_head_motion3.py [OUTPUT]   (default: arm_head.motion3.json next to
this script)
"""

import json
import os
import sys
from fractions import Fraction

FPS = 30
FRAME_COUNT = 91  # frames 0..90

# Segment identifiers (motion3.json spec).
LINEAR, BEZIER, STEPPED, INVERSE_STEPPED = 0, 1, 2, 3

# Each curve: (Id, extra fields, first point (frame, value), segments). A segment is
# (identifier, end frame, end value) or, for a Bezier, (BEZIER, end frame, end value,
# P1 value, P2 value) with P1/P2 at 1/3 and 2/3 of the segment's time span.
CURVES = [
    ("ParamAngleX", {}, (0, 0), [
        (BEZIER, 27, 25, 0, 25),
        (LINEAR, 45, 25),
        (BEZIER, 72, -15, 25, -15),
        (BEZIER, 90, 0, -15, 0),
    ]),
    ("ParamAngleY", {}, (0, 0), [
        (LINEAR, 18, -6),
        (BEZIER, 45, 4, -6, 4),
        (LINEAR, 72, 4),
        (LINEAR, 90, 0),
    ]),
    ("ParamBodyAngleX", {}, (0, 0), [
        (BEZIER, 36, 6, 0, 6),
        (BEZIER, 81, -4, 6, -4),
        (LINEAR, 90, 0),
    ]),
    ("ParamArmLA", {}, (0, 0), [
        (BEZIER, 27, 8, 0, 8),
        (BEZIER, 54, -8, 8, -8),
        (LINEAR, 72, 0),
        (STEPPED, 90, 0),
    ]),
    ("ParamArmRA", {"FadeInTime": Fraction(3, 10), "FadeOutTime": Fraction(3, 10)}, (0, 0), [
        (INVERSE_STEPPED, 9, 0),
        (BEZIER, 36, -8, 0, -8),
        (BEZIER, 63, 8, -8, 8),
        (LINEAR, 90, 0),
    ]),
]

# (frame, value) of the UserData events.
USER_DATA = [(27, "look_right"), (72, "look_left")]


def number(value):
    """An int, or the float nearest to an exact fraction (printed as its shortest decimal)."""
    value = Fraction(value)
    if value.denominator == 1:
        return int(value)
    return float(value)


def seconds(frame):
    return number(Fraction(frame, FPS))


def segments(first, segs):
    """The flat Segments array, and the curve's (segment count, point count)."""
    out = [seconds(first[0]), number(first[1])]
    previous_frame = first[0]
    points = 1
    for seg in segs:
        kind, frame, value = seg[0], seg[1], seg[2]
        out.append(kind)
        if kind == BEZIER:
            span = frame - previous_frame
            assert span % 3 == 0, "handles must fall on whole frames"
            out += [seconds(previous_frame + span // 3), number(seg[3])]
            out += [seconds(previous_frame + 2 * span // 3), number(seg[4])]
            points += 2
        out += [seconds(frame), number(value)]
        points += 1
        previous_frame = frame
    return out, len(segs), points


def motion():
    curves = []
    total_segments = 0
    total_points = 0
    for curve_id, extra, first, segs in CURVES:
        flat, segment_count, point_count = segments(first, segs)
        total_segments += segment_count
        total_points += point_count
        curve = {"Target": "Parameter", "Id": curve_id}
        curve.update({key: number(value) for key, value in extra.items()})
        curve["Segments"] = flat
        curves.append(curve)
    user_data = [{"Time": seconds(frame), "Value": text} for frame, text in USER_DATA]
    meta = {
        "Duration": seconds(FRAME_COUNT - 1),
        "Fps": float(FPS),
        "Loop": True,
        "AreBeziersRestricted": True,
        "FadeInTime": 0.5,
        "FadeOutTime": 0.5,
        "CurveCount": len(curves),
        "TotalSegmentCount": total_segments,
        "TotalPointCount": total_points,
        "UserDataCount": len(user_data),
        "TotalUserDataSize": sum(len(text.encode("utf-8")) for _, text in USER_DATA),
    }
    return {"Version": 3, "Meta": meta, "Curves": curves, "UserData": user_data}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "arm_head.motion3.json")
    text = json.dumps(motion(), indent="\t", ensure_ascii=False) + "\n"
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        out.write(text)


if __name__ == "__main__":
    main()

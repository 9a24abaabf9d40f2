#!/usr/bin/env python3
"""Writes samples/talk_blink.motion3.json: a synthetic Live2D motion for LipBlink.

4 seconds at 30 fps (frames 0-120) of a character who talks and blinks, as a smooth 2D rig
would animate it (the puppet look that LipBlink turns into anime drawings):

  ParamMouthOpenY  two phrases of speech, frames 12-50 and 68-104: the mouth opens and
                   closes smoothly between 0 and 1 with a new peak every 4-6 frames; shut
                   (0) everywhere else;
  ParamEyeLOpen    open (1) with two smooth blinks: closing over 3 frames from frame 27,
                   shut for 2 frames, opening over 4 frames; and a long one from frame 88
                   (shut for 6 frames, opening over 6);
  ParamEyeROpen    the same blinks, one frame later and to 0.05 instead of 0 (eyes are
                   rarely keyed identically), so linked eyes must still blink together;
  ParamAngleX      a slow head turn, which LipBlink must leave untouched.

All segments are linear, all times whole frames. Times are exact fractions of a second printed
as the shortest decimal, and the JSON is written with one tab per level (Cubism Editor's
layout), so the output is byte-identical on every machine.

Usage: python3 make_talk_blink_motion3.py [OUTPUT]   (default: talk_blink.motion3.json next to
this script)
"""

import json
import os
import sys
from fractions import Fraction

FPS = 30
FRAME_COUNT = 121  # frames 0..120
LINEAR = 0


def number(value):
    """An int, or the float nearest to an exact fraction (printed as its shortest decimal)."""
    value = Fraction(value)
    return int(value) if value.denominator == 1 else float(value)


def seconds(frame):
    return number(Fraction(frame, FPS))


def mouth_keys():
    """(frame, value) keys: shut, two phrases of open/close peaks, shut."""
    keys = [(0, 0), (12, 0)]
    peaks = [(15, "0.8"), (18, "0.3"), (22, "1"), (26, "0.2"), (29, "0.6"), (33, "0.1"),
             (37, "0.9"), (41, "0.4"), (44, "0.7"), (48, "0.2"), (50, 0),
             (68, 0), (71, "0.5"), (75, "1"), (79, "0.3"), (83, "0.8"), (86, "0.1"),
             (90, "0.6"), (94, "0.9"), (98, "0.2"), (101, "0.5"), (104, 0), (120, 0)]
    return keys + [(frame, Fraction(value)) for frame, value in peaks]


def blink_keys(delay, shut):
    """An open eye (1) with a short and a long blink, `delay` frames late, shut at `shut`."""
    keys = [(0, 1)]
    for start, closed, opening in ((27, 2, 4), (88, 6, 6)):
        start += delay
        keys += [(start, 1), (start + 3, shut), (start + 3 + closed, shut),
                 (start + 3 + closed + opening, 1)]
    return keys + [(120, 1)]


CURVES = [
    ("ParamMouthOpenY", mouth_keys()),
    ("ParamEyeLOpen", blink_keys(0, 0)),
    ("ParamEyeROpen", blink_keys(1, Fraction(1, 20))),
    ("ParamAngleX", [(0, 0), (60, 10), (120, 0)]),
]


def segments(keys):
    out = [seconds(keys[0][0]), number(keys[0][1])]
    for frame, value in keys[1:]:
        out += [LINEAR, seconds(frame), number(value)]
    return out


def motion():
    curves = [{"Target": "Parameter", "Id": curve_id, "Segments": segments(keys)}
              for curve_id, keys in CURVES]
    segment_count = sum(len(keys) - 1 for _, keys in CURVES)
    meta = {
        "Duration": seconds(FRAME_COUNT - 1),
        "Fps": float(FPS),
        "Loop": False,
        "AreBeziersRestricted": True,
        "CurveCount": len(curves),
        "TotalSegmentCount": segment_count,
        "TotalPointCount": segment_count + len(curves),
    }
    return {"Version": 3, "Meta": meta, "Curves": curves}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "talk_blink.motion3.json")
    text = json.dumps(motion(), indent="\t", ensure_ascii=False) + "\n"
    with open(path, "w", encoding="utf-8", newline="\n") as out:
        out.write(text)


if __name__ == "__main__":
    main()

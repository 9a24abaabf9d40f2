#!/usr/bin/env python3
"""Writes samples/pitch.bvh: a synthetic, pitch-like motion for koma's demos and tests.

130 frames at 24 fps of a 21-joint humanoid (Y up, centimetres, degrees, ZXY rotation
channels). The motion is a right-handed throw towards +Z in three phases:

  frames  0-70   slow wind-up: the left leg lifts, the throwing arm swings back;
  frames 70-85   fast throw: stride landing, torso and throwing arm whip forward;
  frames 85-129  slow follow-through: the arm crosses the body and the pitcher settles.

Each channel is a piecewise cubic Hermite curve through key poses, with Catmull-Rom style
tangents and zero velocity at the first and last key, so the speed rises and falls smoothly
(slow, fast, slow). Only arithmetic is used (no math.sin and friends) and every number is
printed with fixed decimals, so the output is byte-identical on every machine and Python 3.

Usage: python3 make_pitch_bvh.py [OUTPUT]   (default: pitch.bvh next to this script)
"""

import os
import sys

FRAME_COUNT = 130
FRAME_TIME_TEXT = "0.0416667"  # 1/24 s, as most exporters print it
ROT = ("Zrotation", "Xrotation", "Yrotation")
ROOT_CHANNELS = ("Xposition", "Yposition", "Zposition") + ROT

# (name, parent name, offset in cm, end site offset or None)
JOINTS = [
    ("Hips", None, (0.0, 0.0, 0.0), None),
    ("Spine", "Hips", (0.0, 10.0, 0.0), None),
    ("Spine1", "Spine", (0.0, 15.0, 0.0), None),
    ("Neck", "Spine1", (0.0, 20.0, 0.0), None),
    ("Head", "Neck", (0.0, 10.0, 0.0), (0.0, 16.0, 0.0)),
    ("LeftShoulder", "Spine1", (5.0, 17.0, 0.0), None),
    ("LeftArm", "LeftShoulder", (12.0, 0.0, 0.0), None),
    ("LeftForeArm", "LeftArm", (28.0, 0.0, 0.0), None),
    ("LeftHand", "LeftForeArm", (25.0, 0.0, 0.0), (15.0, 0.0, 0.0)),
    ("RightShoulder", "Spine1", (-5.0, 17.0, 0.0), None),
    ("RightArm", "RightShoulder", (-12.0, 0.0, 0.0), None),
    ("RightForeArm", "RightArm", (-28.0, 0.0, 0.0), None),
    ("RightHand", "RightForeArm", (-25.0, 0.0, 0.0), (-15.0, 0.0, 0.0)),
    ("LeftUpLeg", "Hips", (9.0, -5.0, 0.0), None),
    ("LeftLeg", "LeftUpLeg", (0.0, -42.0, 0.0), None),
    ("LeftFoot", "LeftLeg", (0.0, -40.0, 0.0), None),
    ("LeftToe", "LeftFoot", (0.0, -6.0, 13.0), (0.0, 0.0, 6.0)),
    ("RightUpLeg", "Hips", (-9.0, -5.0, 0.0), None),
    ("RightLeg", "RightUpLeg", (0.0, -42.0, 0.0), None),
    ("RightFoot", "RightLeg", (0.0, -40.0, 0.0), None),
    ("RightToe", "RightFoot", (0.0, -6.0, 13.0), (0.0, 0.0, 6.0)),
]

# Key frames and, per key, the channels that differ from 0 (Hips also has its position:
# "Hips.pos" = (x, y, z) cm). Rotations are (z, x, y) degrees, in channel order.
KEY_FRAMES = (0, 45, 70, 78, 85, 129)
KEYS = {
    # set position: side-on to the target, hands together at the chest
    0: {"Hips.pos": (0, 95, 0), "Hips": (0, 0, 90), "Spine": (0, -3, 0),
        "LeftArm": (-70, 0, 40), "LeftForeArm": (0, 0, 100), "RightArm": (70, 0, -40),
        "RightForeArm": (0, 0, -100), "LeftToe": (0, 0, 0)},
    # balance point: left knee up, weight on the right leg
    45: {"Hips.pos": (0, 97, -3), "Hips": (0, 0, 95), "Spine": (0, -6, -5),
         "Spine1": (0, 0, -10), "LeftArm": (-65, 5, 45), "LeftForeArm": (0, 0, 95),
         "RightArm": (65, 5, -45), "RightForeArm": (0, 0, -95), "LeftUpLeg": (0, -85, 0),
         "LeftLeg": (0, 95, 0), "LeftFoot": (0, -20, 0), "RightLeg": (0, 10, 0)},
    # stride landing, arm cocked: hips open, torso still closed, ball hand back and up
    70: {"Hips.pos": (0, 86, 55), "Hips": (0, 5, 60), "Spine": (0, -10, -15),
         "Spine1": (0, -5, -30), "Neck": (0, 0, 25), "LeftArm": (-20, -30, 70),
         "LeftForeArm": (0, 0, 30), "RightArm": (10, -80, -60),
         "RightForeArm": (0, 0, -95), "RightHand": (0, -30, 0), "LeftUpLeg": (0, -50, 0),
         "LeftLeg": (0, 40, 0), "RightUpLeg": (0, 35, 0), "RightLeg": (0, 30, 0),
         "RightFoot": (0, 20, 0)},
    # release: torso square to the target and flexing, arm whipped forward and extended
    78: {"Hips.pos": (0, 84, 64), "Hips": (0, 10, 5), "Spine": (0, 25, 20),
         "Spine1": (0, 15, 35), "Neck": (0, -10, -20), "LeftArm": (-40, 10, -30),
         "LeftForeArm": (0, 0, 70), "RightArm": (-20, -95, 70),
         "RightForeArm": (0, 0, -10), "RightHand": (0, 35, 0), "LeftUpLeg": (0, -40, 0),
         "LeftLeg": (0, 25, 0), "RightUpLeg": (0, 45, 0), "RightLeg": (0, 50, 0),
         "RightFoot": (0, 30, 0)},
    # deceleration: the arm sweeps across the body
    85: {"Hips.pos": (0, 83, 70), "Hips": (0, 15, -10), "Spine": (0, 35, 25),
         "Spine1": (0, 20, 40), "Neck": (0, -15, -25), "LeftArm": (-55, 15, -40),
         "LeftForeArm": (0, 0, 85), "RightArm": (-50, -40, 100),
         "RightForeArm": (0, 0, -30), "RightHand": (0, 20, 0), "LeftUpLeg": (0, -35, 0),
         "LeftLeg": (0, 20, 0), "RightUpLeg": (0, 30, 0), "RightLeg": (0, 70, 0),
         "RightFoot": (0, 35, 0)},
    # finish: back leg through, fielding stance
    129: {"Hips.pos": (0, 88, 78), "Hips": (0, 12, -5), "Spine": (0, 25, 10),
          "Spine1": (0, 10, 15), "Neck": (0, -10, -10), "LeftArm": (-70, 5, -20),
          "LeftForeArm": (0, 0, 60), "RightArm": (-65, -10, 60),
          "RightForeArm": (0, 0, -45), "RightHand": (0, 10, 0), "LeftUpLeg": (0, -25, 0),
          "LeftLeg": (0, 30, 0), "RightUpLeg": (0, -30, 0), "RightLeg": (0, 45, 0),
          "RightFoot": (0, 10, 0)},
}


def channel_keys():
    """Per channel, the list of key values: {('Hips', 'pos', 0): [v0, v1, ...], ...}."""
    curves = {}
    for name, _, _, _ in JOINTS:
        tracks = [("pos", 3)] if name == "Hips" else []
        tracks.append(("rot", 3))
        for kind, count in tracks:
            key = name + ".pos" if kind == "pos" else name
            for i in range(count):
                curves[(name, kind, i)] = [
                    float(KEYS[f].get(key, (0, 0, 0))[i]) for f in KEY_FRAMES]
    return curves


def tangents(values):
    """Catmull-Rom tangents for non-uniform key times, zero at both ends (per frame)."""
    t = KEY_FRAMES
    out = [0.0] * len(values)
    for k in range(1, len(values) - 1):
        out[k] = (values[k + 1] - values[k - 1]) / (t[k + 1] - t[k - 1])
    return out


def evaluate(values, slopes, frame):
    """Cubic Hermite interpolation of the keys at an integer frame."""
    t = KEY_FRAMES
    k = 0
    while k + 2 < len(t) and frame >= t[k + 1]:
        k += 1
    span = t[k + 1] - t[k]
    s = (frame - t[k]) / span
    s2 = s * s  # products, not ** (which calls the C library's pow)
    s3 = s2 * s
    h00 = 2 * s3 - 3 * s2 + 1
    h10 = s3 - 2 * s2 + s
    h01 = -2 * s3 + 3 * s2
    h11 = s3 - s2
    return (h00 * values[k] + h10 * span * slopes[k] + h01 * values[k + 1]
            + h11 * span * slopes[k + 1])


def fixed(value):
    text = "%.4f" % value
    return "0.0000" if text == "-0.0000" else text


def hierarchy_lines():
    children = {name: [] for name, _, _, _ in JOINTS}
    for name, parent, _, _ in JOINTS:
        if parent is not None:
            children[parent].append(name)
    info = {name: (offset, end) for name, _, offset, end in JOINTS}
    lines = ["HIERARCHY"]

    def write(name, depth):
        pad = "\t" * depth
        offset, end = info[name]
        channels = ROOT_CHANNELS if depth == 0 else ROT
        lines.append(pad + ("ROOT " if depth == 0 else "JOINT ") + name)
        lines.append(pad + "{")
        lines.append(pad + "\tOFFSET " + " ".join(fixed(v) for v in offset))
        lines.append(pad + "\tCHANNELS %d %s" % (len(channels), " ".join(channels)))
        for child in children[name]:
            write(child, depth + 1)
        if end is not None:
            lines.extend([pad + "\tEnd Site", pad + "\t{",
                          pad + "\t\tOFFSET " + " ".join(fixed(v) for v in end),
                          pad + "\t}"])
        lines.append(pad + "}")

    write("Hips", 0)
    return lines


def motion_lines():
    curves = channel_keys()
    slopes = {key: tangents(values) for key, values in curves.items()}
    order = []  # channel keys in file order: depth-first joint order equals JOINTS order
    for name, _, _, _ in JOINTS:
        if name == "Hips":
            order += [(name, "pos", i) for i in range(3)]
        order += [(name, "rot", i) for i in range(3)]
    lines = ["MOTION", "Frames: %d" % FRAME_COUNT, "Frame Time: " + FRAME_TIME_TEXT]
    for frame in range(FRAME_COUNT):
        lines.append(" ".join(
            fixed(evaluate(curves[key], slopes[key], frame)) for key in order))
    return lines


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    output = argv[1] if len(argv) > 1 else os.path.join(here, "pitch.bvh")
    text = "\n".join(hierarchy_lines() + motion_lines()) + "\n"
    with open(output, "w", encoding="ascii", newline="\n") as out:
        out.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

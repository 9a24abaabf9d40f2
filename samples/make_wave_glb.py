#!/usr/bin/env python3
"""Writes samples/wave.glb: a small synthetic glTF 2.0 character for koma's examples and tests.

A skinned upper body (Hips, Spine, Head, both arms: 9 joints) and a face quad skinned to the
Head with two morph targets ("smile", "blink"), VRM 1.0-style extensions (VRMC_vrm with meta
and humanoid bones) and extras, and one animation "Wave": 2 s baked at 30 fps (61 LINEAR keys,
as Blender exports), the right arm rising then waving fast, the head nodding slowly, the hips
swaying, a smile growing and one blink. Rotations are quaternions (axis * u, 1) / sqrt(1 + u^2)
(an angle of 2 atan u) with u a rational function of the frame, and every number is computed
exactly (fractions.Fraction; sqrt of a float is correctly rounded) before it becomes a 32-bit
float, so the bytes are the same on every machine.

Usage: python3 make_wave_glb.py [OUTPUT]   (default: wave.glb next to this script)
"""

import json
import math
import os
import struct
import sys
from fractions import Fraction

FPS = 30
FRAMES = 61

JOINTS = [  # name, parent, rest translation (metres)
    ("Hips", -1, (0, 1, 0)),
    ("Spine", 0, (0, Fraction(1, 5), 0)),
    ("Head", 1, (0, Fraction(7, 20), 0)),
    ("UpperArm.R", 1, (Fraction(-1, 5), Fraction(3, 10), 0)),
    ("LowerArm.R", 3, (Fraction(-3, 10), 0, 0)),
    ("Hand.R", 4, (Fraction(-1, 4), 0, 0)),
    ("UpperArm.L", 1, (Fraction(1, 5), Fraction(3, 10), 0)),
    ("LowerArm.L", 6, (Fraction(3, 10), 0, 0)),
    ("Hand.L", 7, (Fraction(1, 4), 0, 0)),
]


def smooth(x):
    """Smoothstep of a Fraction clamped to [0, 1]."""
    x = min(max(x, Fraction(0)), Fraction(1))
    return x * x * (3 - 2 * x)


def quat(axis, u):
    n = math.sqrt(1 + float(u) * float(u))
    return [float(a * u) / n for a in axis] + [1 / n]


def arm_raise(f):  # the right arm rises over frames 0-15 (to about 106 degrees)
    return quat((0, 0, 1), Fraction(-13, 10) * smooth(Fraction(f, 15)))


def forearm_wave(f):  # then waves fast: four swings over frames 15-60
    if f < 15:
        return quat((0, 0, 1), Fraction(0))
    phase = Fraction(f - 15, 45) * 4 % 1
    tri = 1 - abs(2 * phase - 1)  # 0 -> 1 -> 0 each swing
    return quat((0, 0, 1), Fraction(-4, 5) * smooth(tri))


def head_nod(f):  # a slow nod down and back
    return quat((1, 0, 0), Fraction(1, 4) * smooth(Fraction(f, 30)) * smooth(Fraction(60 - f, 30)))


def hips_sway(f):
    return [float(Fraction(1, 50) * (smooth(Fraction(f, 60)) - Fraction(1, 2))), 1.0, 0.0]


def face_weights(f):
    smile = smooth(Fraction(f, 60))
    blink = 1 - abs(Fraction(f - 43, 3)) if 40 <= f <= 46 else Fraction(0)
    return [float(smile), float(blink)]


class Bin:
    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def add(self, values, type_, min_max=False, count=None):
        while len(self.data) % 4:
            self.data.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": 4 * len(values)})
        self.data += struct.pack("<%df" % len(values), *values)
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[type_]
        accessor = {"bufferView": len(self.views) - 1, "componentType": 5126,
                    "count": count or len(values) // width, "type": type_}
        if min_max:
            floats = struct.unpack("<%df" % len(values), struct.pack("<%df" % len(values), *values))
            accessor["min"] = [min(floats[i::width]) for i in range(width)]
            accessor["max"] = [max(floats[i::width]) for i in range(width)]
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "wave.glb")
    b = Bin()
    # The face: a quad in front of the head (world), both triangles on the Head joint.
    head_world = [0, 1 + 0.2 + 0.35, 0]
    quad = [(-0.1, 0.0, 0.12), (0.1, 0.0, 0.12), (0.1, 0.2, 0.12), (-0.1, 0.2, 0.12)]
    positions = [c + h for v in quad for c, h in zip(v, head_world)]
    pos = b.add(positions, "VEC3", min_max=True)
    smile_target = b.add([0, 0, 0, 0, 0, 0, 0, 0.02, 0, 0, 0.02, 0], "VEC3", min_max=True)
    blink_target = b.add([0, 0.05, 0, 0, 0.05, 0, 0, -0.05, 0, 0, -0.05, 0], "VEC3", min_max=True)
    joints = b.add([2, 0, 0, 0] * 4, "VEC4")  # float joints would be invalid: replaced below
    b.accessors[joints] = {"bufferView": b.accessors[joints]["bufferView"], "componentType": 5126,
                           "count": 4, "type": "VEC4"}
    weights = b.add([1, 0, 0, 0] * 4, "VEC4")
    # JOINTS_0 as unsigned bytes, as the spec requires.
    while len(b.data) % 4:
        b.data.append(0)
    b.views.append({"buffer": 0, "byteOffset": len(b.data), "byteLength": 16})
    b.data += bytes([2, 0, 0, 0] * 4)
    b.accessors[joints] = {"bufferView": len(b.views) - 1, "componentType": 5121, "count": 4,
                           "type": "VEC4"}
    index_view = len(b.views)
    b.views.append({"buffer": 0, "byteOffset": len(b.data), "byteLength": 12})
    b.data += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    b.accessors.append({"bufferView": index_view, "componentType": 5123, "count": 6,
                        "type": "SCALAR"})
    indices = len(b.accessors) - 1
    # Inverse bind matrices: the joints' rest world translations, negated (no rest rotation).
    world = []
    for name, parent, t in JOINTS:
        base = world[parent] if parent >= 0 else (0, 0, 0)
        world.append(tuple(base[i] + Fraction(t[i]) for i in range(3)))
    ibm = []
    for w in world:
        ibm += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, float(-w[0]), float(-w[1]), float(-w[2]), 1]
    inverse_bind = b.add(ibm, "MAT4")
    # The animation.
    times = [f / FPS for f in range(FRAMES)]
    t_in = b.add(times, "SCALAR", min_max=True)
    channels, samplers = [], []

    def channel(node, path, values, type_):
        samplers.append({"input": t_in, "interpolation": "LINEAR", "output": b.add(values, type_)})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})

    channel(0, "translation", [x for f in range(FRAMES) for x in hips_sway(f)], "VEC3")
    channel(2, "rotation", [x for f in range(FRAMES) for x in head_nod(f)], "VEC4")
    channel(3, "rotation", [x for f in range(FRAMES) for x in arm_raise(f)], "VEC4")
    channel(4, "rotation", [x for f in range(FRAMES) for x in forearm_wave(f)], "VEC4")
    channel(9, "weights", [x for f in range(FRAMES) for x in face_weights(f)], "SCALAR")

    nodes = []
    for i, (name, parent, t) in enumerate(JOINTS):
        node = {"name": name, "translation": [float(x) for x in t]}
        children = [j for j, joint in enumerate(JOINTS) if joint[1] == i]
        if children:
            node["children"] = children
        nodes.append(node)
    nodes.append({"name": "Face", "mesh": 0, "skin": 0})
    doc = {
        "asset": {"version": "2.0", "generator": "koma samples/make_wave_glb.py"},
        "extensionsUsed": ["VRMC_vrm"],
        "extensions": {"VRMC_vrm": {
            "specVersion": "1.0",
            "meta": {"name": "wave", "version": "1", "authors": ["koma"],
                     "licenseUrl": "https://vrm.dev/licenses/1.0/"},
            "humanoid": {"humanBones": {
                "hips": {"node": 0}, "spine": {"node": 1}, "head": {"node": 2},
                "rightUpperArm": {"node": 3}, "rightLowerArm": {"node": 4},
                "rightHand": {"node": 5}, "leftUpperArm": {"node": 6},
                "leftLowerArm": {"node": 7}, "leftHand": {"node": 8}}}}},
        "scene": 0,
        "scenes": [{"name": "Scene", "nodes": [0, 9]}],
        "nodes": nodes,
        "meshes": [{"name": "Face", "weights": [0, 0], "extras": {"targetNames": ["smile", "blink"]},
                    "primitives": [{"attributes": {"POSITION": pos, "JOINTS_0": joints,
                                                   "WEIGHTS_0": weights},
                                    "indices": indices,
                                    "targets": [{"POSITION": smile_target},
                                                {"POSITION": blink_target}]}]}],
        "skins": [{"name": "Body", "joints": list(range(len(JOINTS))),
                   "inverseBindMatrices": inverse_bind}],
        "animations": [{"name": "Wave", "channels": channels, "samplers": samplers}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.data)}],
        "extras": {"sample": "koma"},
    }
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    data = bytes(b.data) + b"\0" * (-len(b.data) % 4)
    total = 12 + 8 + len(text) + 8 + len(data)
    with open(out, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(text), b"JSON") + text)
        f.write(struct.pack("<I4s", len(data), b"BIN\0") + data)


if __name__ == "__main__":
    main()

"""Writes a tree of small, varied clips for the `koma batch` end-to-end tests.

Usage: batch_make_clips.py ROOT BVH MOTION3 CSV [SEED]
  ROOT/bvh/gNN/clip_NNNN.bvh      BVH clips, 2-5 joints, 24-60 frames at 30 fps
  ROOT/curves/gNN/clip_NNNN.motion3.json   motion3.json, 2-4 linear curves, 1-3 s
  ROOT/curves/gNN/clip_NNNN.csv   per-frame CSV, 2-3 curves, 30-90 frames
and the bad ones, listed one per line (path, then what is wrong) in ROOT/bad.txt:
  bvh/bad/garbage.bvh (not a BVH), bvh/bad/short_motion.bvh (fewer values than frames x
  channels), bvh/bad/one_frame.bvh (valid, but 1 frame: the server refuses it),
  curves/bad/broken.motion3.json (not JSON), curves/bad/ragged.csv (a row missing a field).
Deterministic for a seed (Python's random), so a failure can be reproduced.
"""
import json
import math
import os
import random
import sys


def bvh_text(rng, joints, frames):
    lines = ["HIERARCHY", "ROOT Hips", "{", "\tOFFSET 0 0 0",
             "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"]
    for j in range(1, joints):
        indent = "\t" * j
        lines += [f"{indent}JOINT J{j}", indent + "{",
                  f"{indent}\tOFFSET 0 {rng.uniform(5, 15):.4f} 0",
                  f"{indent}\tCHANNELS 3 Zrotation Xrotation Yrotation"]
    indent = "\t" * joints
    lines += [indent + "End Site", indent + "{", indent + "\tOFFSET 0 5 0", indent + "}"]
    for j in range(joints - 1, -1, -1):
        lines.append("\t" * j + "}")
    lines += ["MOTION", f"Frames: {frames}", "Frame Time: 0.0333333"]
    channels = 6 + 3 * (joints - 1)
    params = [(rng.uniform(5, 60), rng.uniform(0.5, 3), rng.uniform(0, 6.3)) for _ in range(channels)]
    for f in range(frames):
        t = f / 30.0
        values = [a * math.sin(w * t * 2 * math.pi + p) for a, w, p in params]
        lines.append(" ".join(f"{v:.4f}" for v in values))
    return "\n".join(lines) + "\n"


def motion3_text(rng):
    duration = rng.choice([1.0, 1.5, 2.0, 3.0])
    curves = []
    segments = points = 0
    for c in range(rng.randint(2, 4)):
        keys = sorted({0.0, duration} | {round(rng.uniform(0.1, duration - 0.1), 2)
                                           for _ in range(rng.randint(1, 4))})
        seg = [keys[0], round(rng.uniform(-30, 30), 3)]
        for t in keys[1:]:
            seg += [0, t, round(rng.uniform(-30, 30), 3)]
        segments += len(keys) - 1
        points += len(keys)
        curves.append({"Target": "Parameter", "Id": f"Param{c}", "Segments": seg})
    doc = {"Version": 3,
           "Meta": {"Duration": duration, "Fps": 30.0, "Loop": False,
                    "AreBeziersRestricted": True, "CurveCount": len(curves),
                    "TotalSegmentCount": segments, "TotalPointCount": points,
                    "UserDataCount": 0, "TotalUserDataSize": 0},
           "Curves": curves}
    return json.dumps(doc, indent=1) + "\n"


def csv_text(rng):
    frames = rng.randint(30, 90)
    ids = [f"Param{c}" for c in range(rng.randint(2, 3))]
    params = [(rng.uniform(1, 30), rng.uniform(0.3, 2), rng.uniform(0, 6.3)) for _ in ids]
    rows = ["frame," + ",".join(ids)]
    for f in range(frames):
        rows.append(",".join([str(f)] + [f"{a * math.sin(w * f / 30.0 * 6.283 + p):.4f}"
                                         for a, w, p in params]))
    return "\n".join(rows) + "\n"


def write(root, relative, text):
    path = os.path.join(root, relative)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def main():
    root, n_bvh, n_motion3, n_csv = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    rng = random.Random(int(sys.argv[5]) if len(sys.argv) > 5 else 1)
    for i in range(n_bvh):
        write(root, f"bvh/g{i % 10:02d}/clip_{i:04d}.bvh",
              bvh_text(rng, rng.randint(2, 5), rng.randint(24, 60)))
    for i in range(n_motion3):
        write(root, f"curves/g{i % 10:02d}/clip_{i:04d}.motion3.json", motion3_text(rng))
    for i in range(n_csv):
        # Numbered after the motion3 clips: a clip's timing sheet is NAME.timing.csv.
        write(root, f"curves/g{i % 10:02d}/clip_{n_motion3 + i:04d}.csv", csv_text(rng))
    bad = {
        "bvh/bad/garbage.bvh": "this is not a BVH file\n",
        "bvh/bad/short_motion.bvh": bvh_text(rng, 2, 30).rsplit("\n", 5)[0] + "\n",
        "bvh/bad/one_frame.bvh": bvh_text(rng, 2, 1),
        "curves/bad/broken.motion3.json": '{"Version": 3, "Meta": {\n',
        "curves/bad/ragged.csv": "frame,ParamA,ParamB\n0,1,2\n1,3\n2,5,6\n",
    }
    for relative, text in bad.items():
        write(root, relative, text)
    with open(os.path.join(root, "bad.txt"), "w") as f:
        f.write("\n".join(bad) + "\n")


main()

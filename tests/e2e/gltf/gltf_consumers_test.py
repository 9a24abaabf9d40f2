#!/usr/bin/env python3
"""glTF through koma, read back by two consumers that are not koma's (issue 31's acceptance).

Real files no one here wrote: Debian's Blender 3.4 imports the real BVHs of tests/testdata and
writes them with its glTF exporter (io_scene_gltf2), one with a skinned mesh whose two shape
keys are animated (morph targets), as .glb and as embedded .gltf. `koma skeletal` retimes each
through a real koma_server on 127.0.0.1, then:
  - Blender's glTF importer: at every output frame the world head of every bone (and every
    shape key's value) equals the source's at the timing sheet's source frame, within 1e-4 of
    the rig's size;
  - three.js (GLTFLoader + AnimationMixer under node): the same at every output frame time, and
    with STEP keys nothing moves halfway between two frames of one drawing.

Usage: gltf_consumers_test.py KOMA_SERVER KOMA BLENDER TESTDATA_DIR WORKDIR
"""
import csv
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "testing"))
from koma_server import KomaServer  # noqa: E402

server_bin, koma_bin, blender, testdata, workdir = sys.argv[1:6]
os.makedirs(workdir, exist_ok=True)
if not os.path.isdir(os.path.join(HERE, "node_modules", "three")):
    sys.exit("three.js is not installed in tests/e2e/gltf/node_modules: run ./scripts/install-deps.sh")

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


def run(args, timeout=300):
    result = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        sys.exit(f"{' '.join(args)} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return result.stdout


def blender_script(script, *args):
    return run([blender, "-b", "--factory-startup", "--python", os.path.join(HERE, script),
                "--", *args])


def distance(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def rig_size(nodes):
    coords = list(nodes.values())
    return max(max(c[i] for c in coords) - min(c[i] for c in coords) for i in range(3))


# (BVH, container, with a skinned mesh and shape keys, extra `koma skeletal` flags)
CASES = [
    ("bvh_test1.bvh", ".glb", True, []),
    ("bvh_test2.bvh", ".gltf", False, ["--gltf-keys", "linear"]),
    ("bvh_test1.bvh", ".glb", True, ["--output-rate", "timing", "--omit", "6"]),
    ("bvh_test3.bvh", ".glb", False, ["--timing-fps", "0", "--hold", "40"]),
]

server = KomaServer(server_bin, workdir)
try:
    for n, (bvh, container, morph, flags) in enumerate(CASES):
        name = f"case{n}_{os.path.splitext(bvh)[0]}"
        source = os.path.join(workdir, name + container)
        blender_script("blender_export.py", os.path.join(testdata, bvh), source,
                       "morph" if morph else "plain")
        out = os.path.join(workdir, name + "_anime" + container)
        timing = os.path.join(workdir, name + "_timing.csv")
        summary = json.loads(run([koma_bin, "skeletal", source, "-o", out, "--timing", timing,
                                  "--server", server.address, "--json", *flags]))
        src_fps, out_fps = summary["input_fps"], summary["output_fps"]
        with open(timing) as f:
            shown = [int(row["source_frame"]) for row in csv.DictReader(f)]
        out_frames = list(range(len(shown)))
        src_frames = sorted(set(shown))
        step = "--gltf-keys" not in flags
        print(f"{name}: {summary['input_frames']} frames at {src_fps} fps -> {len(shown)} at "
              f"{out_fps} fps, {summary['omissions_applied']} omitted, "
              f"{summary['holds_applied']} holds")
        check(summary["omissions_applied"] > 0, f"{name}: nothing omitted")

        # Blender's importer, at each file's own rate.
        src_json, out_json = (os.path.join(workdir, f"{name}_{k}_blender.json")
                              for k in ("src", "out"))
        blender_script("blender_poses.py", source, str(round(src_fps)), src_json,
                       ",".join(map(str, src_frames)))
        blender_script("blender_poses.py", out, str(round(out_fps)), out_json,
                       ",".join(map(str, out_frames)))
        src_poses = json.load(open(src_json))["poses"]
        out_poses = json.load(open(out_json))["poses"]
        size = rig_size(src_poses[str(src_frames[0])]["bones"])
        worst = 0.0
        for t, s in enumerate(shown):
            a, b = out_poses[str(t)], src_poses[str(s)]
            check(a["bones"].keys() == b["bones"].keys(), f"{name}: Blender bones differ")
            for bone, head in a["bones"].items():
                worst = max(worst, distance(head, b["bones"][bone]) / size)
            for key, value in b["keys"].items():
                check(abs(a["keys"][key] - value) <= 1e-4,
                      f"{name}: Blender shape key {key} at output frame {t}: "
                      f"{a['keys'][key]} != {value}")
        check(worst <= 1e-4, f"{name}: Blender bone heads off by {worst} of the rig's size")
        print(f"  Blender: {len(shown)} output frames, worst bone head {worst:.2e} of the rig "
              f"({size:.3g} units)")

        # three.js, at every output frame time (and halfway, for STEP).
        src_json, out_json = (os.path.join(workdir, f"{name}_{k}_three.json")
                              for k in ("src", "out"))
        run(["node", os.path.join(HERE, "three_poses.mjs"), source, str(src_fps), src_json,
             ",".join(map(str, src_frames))])
        run(["node", os.path.join(HERE, "three_poses.mjs"), out, str(out_fps), out_json,
             ",".join(map(str, out_frames)), "half"])
        src_three = json.load(open(src_json))
        out_three = json.load(open(out_json))
        check(out_three["interpolations"] == ([2300] if step else [2301]),
              f"{name}: three.js interpolations {out_three['interpolations']}")
        size = rig_size(src_three["poses"][str(src_frames[0])]["nodes"])
        worst = 0.0
        moved_inside = 0
        for t, s in enumerate(shown):
            a, b = out_three["poses"][str(t)], src_three["poses"][str(s)]
            for node, position in b["nodes"].items():
                worst = max(worst, distance(a["nodes"][node], position) / size)
            for mesh, influences in b["morphs"].items():
                check(distance(a["morphs"][mesh], influences) <= 1e-5,
                      f"{name}: three.js morphs of {mesh} at output frame {t}")
            if step and t + 1 < len(shown) and shown[t + 1] == s:
                inside = out_three["poses"][f"{t}.5"]
                if inside != a:
                    moved_inside += 1
        check(worst <= 1e-4, f"{name}: three.js positions off by {worst} of the rig's size")
        check(moved_inside == 0, f"{name}: three.js pose changed inside {moved_inside} drawings")
        print(f"  three.js: worst position {worst:.2e} of the rig; held drawings still: "
              f"{moved_inside == 0}")
finally:
    server.stop()

if failures:
    sys.exit(f"{len(failures)} failures")
print("gltf consumers: OK")

"""blender.fbx_positions: each FBX file of a folder imported by Blender's own FBX importer
(headless), against koma's reading of it (fbx_positions): every bone's head and every Null's
location in world space, at every frame of the take.

Blender converts axes and units on import (Y up to Z up, centimetres to metres): the one
similarity transform (scale, rotation, translation) that best maps koma's positions to
Blender's on the first frame is fitted, then every frame must agree within 1e-4 of the
character's size.

  blender -b --factory-startup --python blender_positions_test.py -- FBX_POSITIONS FOLDER
"""
import json
import os
import subprocess
import sys

import bpy
from mathutils import Matrix, Vector

FRAMES = 40


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def blender_positions(path, names, fps, start_s, frames=FRAMES):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.fbx(filepath=path)
    scene = bpy.context.scene
    by_name = {}
    for obj in scene.objects:
        by_name.setdefault(obj.name, ('object', obj))
        if obj.type == 'ARMATURE':
            for bone in obj.pose.bones:
                by_name[bone.name] = ('bone', (obj, bone))
    missing = [n for n in names if n not in by_name]
    if missing:
        fail('%s: Blender has no bone or object named %s' % (path, missing))
    out = []
    # Blender's importer puts the take's start at its frame start * fps + 1 (anim_offset 1).
    first = start_s * fps + 1.0
    for f in range(frames):
        scene.frame_set(int(round(first + f)))
        bpy.context.view_layer.update()
        frame = []
        for n in names:
            kind, what = by_name[n]
            if kind == 'bone':
                arm, bone = what
                p = arm.matrix_world @ bone.head
            else:
                p = what.matrix_world.translation
            frame.append([p.x, p.y, p.z])
        out.append(frame)
    return out


def fit(source, target):
    """Umeyama: scale s, rotation R, translation t minimising |s R x + t - y|."""
    import numpy as np
    x = np.array(source)
    y = np.array(target)
    mx, my = x.mean(0), y.mean(0)
    xc, yc = x - mx, y - my
    cov = yc.T @ xc / len(x)
    u, d, vt = np.linalg.svd(cov)
    sign = np.eye(3)
    if np.linalg.det(u) * np.linalg.det(vt) < 0:
        sign[2, 2] = -1
    r = u @ sign @ vt
    var = (xc ** 2).sum() / len(x)
    s = np.trace(np.diag(d) @ sign) / var
    t = my - s * r @ mx
    return s, r, t


def main():
    args = sys.argv[sys.argv.index('--') + 1:]
    tool, folder = args[0], args[1]
    import numpy as np
    files = sorted(f for f in os.listdir(folder) if f.endswith('.fbx'))
    checked = 0
    for name in files:
        path = os.path.join(folder, name)
        koma = json.loads(subprocess.run([tool, path, str(FRAMES)], check=True,
                                         capture_output=True, text=True).stdout)
        keep = [i for i, t in enumerate(koma['types']) if t in ('LimbNode', 'Null', 'Root')]
        if len(keep) < 3:
            print('%s: %d bones or Nulls, not a skeleton: skipped' % (name, len(keep)))
            continue
        names = [koma['names'][i] for i in keep]
        ours = [[frame[i] for i in keep] for frame in koma['positions']]
        theirs = blender_positions(path, names, koma['fps'], koma['start_s'])
        s, r, t = fit(ours[0], theirs[0])
        size = np.ptp(np.array(theirs[0]), axis=0).max()
        worst = 0.0
        for f in range(FRAMES):
            mapped = (s * (r @ np.array(ours[f]).T)).T + t
            worst = max(worst, float(np.abs(mapped - np.array(theirs[f])).max()))
        print('%s: %d nodes x %d frames, scale %.4g, worst difference %.3g (size %.3g)' % (
            name, len(names), FRAMES, s, worst, size))
        if worst > 1e-4 * max(size, 1e-9):
            fail('%s: koma and Blender differ by %.3g (size %.3g)' % (name, worst, size))
        checked += 1
    if checked < 2:
        fail('only %d files compared' % checked)
    print('fbx positions against Blender: PASS (%d files)' % checked)


if __name__ == '__main__':
    main()

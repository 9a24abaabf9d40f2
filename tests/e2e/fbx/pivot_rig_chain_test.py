"""fbx.pivot_rig_chain: koma's transform chain (fbx_positions) on the Mixamo-style rigs of
make_pivot_rig.py, against the FBX SDK's documented chain evaluated here from the generator's
own data, independently of any FBX reader:

  World = ParentWorld * T * Roff * Rp * Rpre * R * Rpost^-1 * Rp^-1 * Soff * Sp * S * Sp^-1

R in the joint's RotationOrder, Rpre and Rpost in XYZ (RotationActive is 1 on every joint).
Blender's importer agrees with koma on the committed file (blender.fbx_positions); this also
covers what Blender 3.4 reads otherwise, in --strict's rig: pre-rotations about several axes
on joints of another RotationOrder (Blender turns them in the joint's order), post-rotations
that are not their own inverse (Blender applies Rpost uninverted), non-uniform scaling at rest
(Blender's bones drop it). Both rigs as FBX 7.4 and 7.5 (32- and 64-bit node records).
Also: the committed tests/testdata/fbx/koma_mixamo_style_pivots.fbx is the generator's output.

  python3 pivot_rig_chain_test.py FBX_POSITIONS COMMITTED_FBX
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_pivot_rig as rig  # noqa: E402

ORDERS = ['XYZ', 'XZY', 'YZX', 'YXZ', 'ZXY', 'ZYX']  # FBX's RotationOrder 0-5


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def axis_rotation(axis, degrees):
    a = math.radians(degrees)
    m = np.eye(4)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    m[i, i], m[i, j], m[j, i], m[j, j] = math.cos(a), -math.sin(a), math.sin(a), math.cos(a)
    return m


def euler(degrees, order):
    """The rotation applying the axes in `order`, first to last."""
    m = np.eye(4)
    for name in ORDERS[order]:
        axis = 'XYZ'.index(name)
        m = axis_rotation(axis, degrees[axis]) @ m
    return m


def translation(v, sign=1.0):
    m = np.eye(4)
    m[:3, 3] = sign * np.array(v, dtype=float)
    return m


def value_at(curve, frame):
    """A curve at a whole frame: every curve of the rigs is keyed on every frame or is a
    straight line between its keys there (linear, or cubic with tangents along the segment)."""
    frames = curve['frames']
    values = [float(np.float32(v)) for v in curve['values']]  # KeyValueFloat
    if frame <= frames[0]:
        return values[0]
    if frame >= frames[-1]:
        return values[-1]
    for k in range(len(frames) - 1):
        if frames[k] <= frame < frames[k + 1]:
            if frame == frames[k]:
                return values[k]
            assert curve['kind'] in ('linear', 'cubic'), curve['kind']
            s = (frame - frames[k]) / (frames[k + 1] - frames[k])
            return values[k] + s * (values[k + 1] - values[k])
    raise AssertionError(frame)


def documented_positions(strict, frames):
    joints = rig.joints(strict)
    animation = rig.animation()
    out = np.zeros((frames, len(joints), 3))
    for f in range(frames):
        world = {}
        for j, (name, parent, t, order, pre, post, rp, roff, sp, soff, s) in enumerate(joints):
            channels = {'T': list(t), 'R': list(rig.rest_rotation(name)), 'S': list(s)}
            for channel, values in channels.items():
                for axis in range(3):
                    if (name, channel, axis) in animation:
                        values[axis] = value_at(animation[name, channel, axis], f)
            local = (translation(channels['T']) @ translation(roff) @ translation(rp) @
                     euler(pre, 0) @ euler(channels['R'], order) @ euler(post, 0).T @
                     translation(rp, -1) @ translation(soff) @ translation(sp) @
                     np.diag(channels['S'] + [1.0]) @ translation(sp, -1))
            world[name] = local if parent is None else world[parent] @ local
            out[f, j] = world[name][:3, 3]
    return out


def main():
    tool, committed = sys.argv[1], sys.argv[2]
    frames = rig.FRAMES
    checked = 0
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, 'rig.fbx')
        rig.write_fbx(path, rig.build(False, 7400), 7400)
        with open(path, 'rb') as a, open(committed, 'rb') as b:
            if a.read() != b.read():
                fail('%s is not what make_pivot_rig.py writes: regenerate it (python3 '
                     'tests/e2e/fbx/make_pivot_rig.py %s)' % (committed, committed))
        for strict in (False, True):
            expected = documented_positions(strict, frames)
            size = np.abs(expected).max()
            for version in (7400, 7500):
                path = os.path.join(folder, 'rig.fbx')
                rig.write_fbx(path, rig.build(strict, version), version)
                koma = json.loads(subprocess.run([tool, path, str(frames)], check=True,
                                                 capture_output=True, text=True).stdout)
                if koma['fps'] != rig.FPS:
                    fail('koma reads %s fps, the file has %d' % (koma['fps'], rig.FPS))
                names = ['mixamorig:' + j[0] for j in rig.joints(strict)]
                if koma['names'] != names:
                    fail('koma reads the joints %s' % koma['names'])
                got = np.array(koma['positions'])
                worst = float(np.abs(got - expected).max())
                joint = int(np.abs(got - expected).max(axis=(0, 2)).argmax())
                label = '%s FBX %d' % ('--strict' if strict else 'committed', version)
                print('%s: %d joints x %d frames, worst difference %.3g (%s; coordinates up '
                      'to %.3g)' % (label, len(names), frames, worst, names[joint], size))
                # Double precision throughout on both sides, from the same float keys.
                if worst > 1e-8 * size:
                    fail('%s: koma differs from the documented chain by %.3g at %s' % (
                        label, worst, names[joint]))
                checked += 1
    print('pivot rig against the documented chain: PASS (%d files)' % checked)


main()

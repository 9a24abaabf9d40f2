"""Debian's assimp (assimp_poses: pivots off) against koma: in each written NAME.anime.fbx of
DIR, at every output frame, every bone's and Null's world position equals the source's at the
source frame NAME.timing.csv says that frame shows. assimp keeps the file's units and axes and
ignores key interpolation (it interpolates linearly): the holds must come from the keys.

The source's positions are koma's (fbx_positions), and assimp must first read the source
itself as koma does. Files named with --own-reading are the exception: assimp 5.2 cannot
evaluate them (a node with a rotation or scaling pivot or offset gets its animation on
"NAME_$AssimpFbx$_Rotation"-style channels, which with pivots off name no node, so the node
stays at rest; with pivots on, it applies them twice; and it turns PostRotation uninverted on
animated nodes). For those, what assimp shows of the written file must equal what it shows of
the source at the source frame, and how far its reading of the source is from koma's is
printed, not checked.

  python3 assimp_retimed_check.py ASSIMP_POSES FBX_POSITIONS DIR [--own-reading NAME]...
"""
import argparse
import csv
import json
import os
import subprocess
import sys


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def assimp(tool, path, frames, fps, start_s):
    out = subprocess.run([tool, path, str(frames), repr(fps), repr(start_s)],
                         capture_output=True, text=True)
    if out.returncode != 0:
        fail('assimp_poses %s: %s' % (path, out.stderr.strip()))
    return json.loads(out.stdout)['poses']


def worst_of(a, b, frames_a, frames_b, names):
    """The largest coordinate difference between a[frames_a[k]] and b[frames_b[k]]."""
    worst = 0.0
    for fa, fb in zip(frames_a, frames_b):
        for n in names:
            worst = max(worst, max(abs(x - y) for x, y in zip(a[fa][n], b[fb][n])))
    return worst


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('assimp_poses')
    parser.add_argument('fbx_positions')
    parser.add_argument('folder')
    parser.add_argument('--own-reading', action='append', default=[])
    args = parser.parse_args()
    checked = 0
    for name in sorted(os.listdir(args.folder)):
        if not name.endswith('.fbx') or name.endswith('.anime.fbx'):
            continue
        stem = name[:-4]
        source_path = os.path.join(args.folder, name)
        rows = list(csv.DictReader(open(os.path.join(args.folder, stem + '.timing.csv'))))
        shown = [int(r['source_frame']) for r in rows]
        frames = max(shown) + 1
        koma = json.loads(subprocess.run([args.fbx_positions, source_path, str(frames)],
                                         check=True, capture_output=True, text=True).stdout)
        keep = [i for i, t in enumerate(koma['types']) if t in ('LimbNode', 'Null', 'Root')]
        names = [koma['names'][i] for i in keep]
        by_name = [{koma['names'][i]: koma['positions'][f][i] for i in keep}
                   for f in range(frames)]
        source = assimp(args.assimp_poses, source_path, frames, koma['fps'], koma['start_s'])
        written = assimp(args.assimp_poses, os.path.join(args.folder, stem + '.anime.fbx'),
                         len(shown), koma['fps'], koma['start_s'])
        for what, poses in (('source', source), ('written file', written)):
            missing = [n for n in names if n not in poses[0]]
            if missing:
                fail('%s: assimp has no node named %s in the %s' % (stem, missing, what))
        size = max(abs(x) for frame in by_name for p in frame.values() for x in p)
        # KeyValueFloat holds floats; assimp computes in float32 too.
        tolerance = 1e-4 * max(size, 1e-9)
        every = list(range(frames))
        apart = worst_of(source, by_name, every, every, names)
        if stem in args.own_reading:
            reference, label = source, "assimp's own reading of the source"
            print('%s: assimp reads the source %.3g away from koma (its pivot handling; not '
                  'checked)' % (stem, apart))
        else:
            if apart > tolerance:
                fail('%s: assimp reads the source %.3g away from koma (coordinates up to %.3g)'
                     % (stem, apart, size))
            reference, label = by_name, "koma's reading of the source"
        worst = worst_of(written, reference, range(len(shown)), shown, names)
        moving = worst_of(reference, reference, shown[1:], shown[:-1], names)
        print('%s: %d output frames, %d nodes, worst difference %.3g from %s (coordinates up '
              'to %.3g; assimp and koma on the source: %.3g)' % (
                  stem, len(shown), len(names), worst, label, size, apart))
        if moving <= tolerance:
            fail('%s: the source does not move as assimp reads it: nothing checked' % stem)
        if worst > tolerance:
            fail('%s: assimp shows the written file %.3g away from the source' % (stem, worst))
        checked += 1
    if checked == 0:
        fail('no file compared')
    print('retimed fbx against assimp: PASS (%d files)' % checked)


main()

"""three.js's FBXLoader (tests/e2e/gltf/three_fbx_poses.mjs, under node) against koma: in each
written NAME.anime.fbx of DIR, at every output frame, every bone's and Null's world position
equals the source's at the source frame NAME.timing.csv says that frame shows (koma's reading
of NAME.fbx, fbx_positions). three.js keeps the file's units and axes and interpolates keys
linearly whatever their flags: the holds must come from the keys themselves.

--skip NAME leaves a file out, for what three.js cannot read (the caller says why).

  python3 three_retimed_check.py FBX_POSITIONS THREE_FBX_POSES_MJS DIR [--skip NAME]...
"""
import csv
import json
import os
import re
import subprocess
import sys


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def main():
    tool, script, folder = (os.path.abspath(a) for a in sys.argv[1:4])
    skip = [sys.argv[i + 1] for i in range(4, len(sys.argv) - 1) if sys.argv[i] == '--skip']
    checked = 0
    for name in sorted(os.listdir(folder)):
        if not name.endswith('.fbx') or name.endswith('.anime.fbx'):
            continue
        stem = name[:-4]
        if stem in skip:
            print('%s: skipped' % stem)
            continue
        rows = list(csv.DictReader(open(os.path.join(folder, stem + '.timing.csv'))))
        shown = [int(r['source_frame']) for r in rows]
        koma = json.loads(subprocess.run([tool, os.path.join(folder, name), str(max(shown) + 1)],
                                         check=True, capture_output=True, text=True).stdout)
        keep = [i for i, t in enumerate(koma['types']) if t in ('LimbNode', 'Null', 'Root')]
        out_json = os.path.join(folder, stem + '.three.json')
        subprocess.run(['node', script, os.path.join(folder, stem + '.anime.fbx'),
                        str(len(shown)), out_json, str(koma['fps'])],
                       check=True, cwd=os.path.dirname(script))
        three = json.load(open(out_json))['poses']
        worst = 0.0
        size = 0.0
        for k, f in enumerate(shown):
            for i in keep:
                # three.js names objects without the characters its bindings reserve ("Bone.001"
                # is "Bone001").
                key = re.sub(r'[\[\]\.:/]', '', koma['names'][i])
                if key not in three[k]:
                    fail('%s: three.js has no object %r' % (stem, key))
                a, b = koma['positions'][f][i], three[k][key]
                worst = max(worst, max(abs(x - y) for x, y in zip(a, b)))
                size = max(size, max(abs(x) for x in a))
        print('%s: %d output frames, %d nodes, worst difference %.3g (coordinates up to %.3g)' % (
            stem, len(shown), len(keep), worst, size))
        # KeyValueFloat holds floats; three.js computes in float32 too.
        if worst > 1e-4 * max(size, 1e-9):
            fail('%s: three.js shows the written file %.3g away from the source' % (stem, worst))
        checked += 1
    if checked == 0:
        fail('no file compared')
    print('retimed fbx against three.js: PASS (%d files)' % checked)


main()

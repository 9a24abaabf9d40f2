"""blender.fbx_retimed: the FBX files `koma skeletal IN.fbx -o OUT.fbx` wrote, imported by
Blender's own FBX importer (headless): at every output frame each bone's and Null's world
position equals the source's at the source frame the timing sheet says that frame shows
(koma's reading of the source, fbx_positions, mapped by the similarity Blender's axis and unit
conversion is, fitted on the source's first frame). Blender interpolates linearly whatever the
flags say, so this also shows that the holds survive a reader that ignores constant keys.

  blender -b --factory-startup --python blender_retimed_test.py -- FBX_POSITIONS DIR
  DIR holds NAME.fbx (the source), NAME.anime.fbx (koma's output) and NAME.timing.csv.
"""
import csv
import json
import os
import subprocess
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_positions_test import blender_positions, fail, fit  # noqa: E402


def main():
    args = sys.argv[sys.argv.index('--') + 1:]
    tool, folder = args[0], args[1]
    import numpy as np
    sources = sorted(f for f in os.listdir(folder)
                     if f.endswith('.fbx') and not f.endswith('.anime.fbx'))
    checked = 0
    for name in sources:
        stem = name[:-4]
        rows = list(csv.DictReader(open(os.path.join(folder, stem + '.timing.csv'))))
        shown = [int(r['source_frame']) for r in rows]
        frames = max(shown) + 1
        koma = json.loads(subprocess.run([tool, os.path.join(folder, name), str(frames)],
                                         check=True, capture_output=True, text=True).stdout)
        keep = [i for i, t in enumerate(koma['types']) if t in ('LimbNode', 'Null', 'Root')]
        names = [koma['names'][i] for i in keep]
        source = [[frame[i] for i in keep] for frame in koma['positions']]
        out_path = os.path.join(folder, stem + '.anime.fbx')
        theirs = blender_positions(out_path, names, koma['fps'], koma['start_s'],
                                   frames=len(shown))
        s, r, t = fit(source[0], theirs[0])
        size = np.ptp(np.array(theirs[0]), axis=0).max()
        worst = 0.0
        for k, f in enumerate(shown):
            mapped = (s * (r @ np.array(source[f]).T)).T + t
            worst = max(worst, float(np.abs(mapped - np.array(theirs[k])).max()))
        holds = sum(1 for k in range(1, len(shown)) if shown[k] == shown[k - 1])
        print('%s: %d output frames (%d holding the frame before), %d nodes, worst difference '
              '%.3g (size %.3g)' % (stem, len(shown), holds, len(names), worst, size))
        if holds == 0:
            fail('%s: the timing has no hold' % stem)
        # KeyValueFloat holds floats: a float's precision of the character's size.
        if worst > 1e-4 * max(size, 1e-9):
            fail('%s: the retimed file differs from the source at its timing by %.3g' % (
                stem, worst))
        checked += 1
    if checked == 0:
        fail('no file compared')
    print('retimed fbx against Blender: PASS (%d files)' % checked)


main()

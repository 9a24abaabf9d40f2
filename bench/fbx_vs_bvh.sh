#!/usr/bin/env bash
# An FBX take against the same motion as BVH, through the RPC (issue 43's speed target: within
# 2x). The motion: tests/testdata/bvh_test3.bvh (60 joints, 120 fps) played forwards and
# backwards to FRAMES frames; Blender's own FBX exporter writes it as binary FBX 7.4 (baked at
# 120 fps, a key per frame on every channel). Each round times, alternately, `koma skeletal take.fbx -o
# out.fbx` and `koma skeletal take.bvh -o out.bvh --send-file` (the file read by the server
# either way) against one koma_server on loopback; prints each round and the medians of the
# times and of the per-round ratio fbx/bvh.
#   bench/fbx_vs_bvh.sh                       (ROUNDS=5 FRAMES=10000; KEEP_TAKE=DIR keeps the
#                                              take.fbx and take.bvh made, for profiling)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD_DIR:-$root/build}
rounds=${ROUNDS:-5}
frames=${FRAMES:-10000}
koma=$build/client/koma
# shellcheck source=tests/e2e/lib.sh
source "$root/tests/e2e/lib.sh"  # $work, start_server ($server_pid, $target), stop_server

python3 - "$root/tests/testdata/bvh_test3.bvh" "$frames" "$work/take.bvh" <<'PY'
import sys
text = open(sys.argv[1]).read()
head, motion = text.split("MOTION", 1)
lines = [l for l in motion.strip().splitlines() if l.strip()]
rows = lines[2:]
n = int(sys.argv[2])
cycle = rows + rows[-2:0:-1]
out = [head, "MOTION\nFrames: %d\n" % n, lines[1] + "\n"]
out += [cycle[i % len(cycle)] + "\n" for i in range(n)]
open(sys.argv[3], "w").write("".join(out))
PY
# Debian's Blender 3.4 BVH importer opens files in mode 'rU', which its Python 3.11 refuses:
# the importer's module gets an open() without the U.
blender -b --factory-startup --python-exit-code 1 --python-expr "
import builtins, bpy, sys
from io_anim_bvh import import_bvh
import_bvh.open = lambda path, mode='r', *a, **k: builtins.open(path, mode.replace('U', ''), *a, **k)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_anim.bvh(filepath='$work/take.bvh', update_scene_fps=False, update_scene_duration=True)
# A whole rate (the file's 1 / 0.008333 s is 120.0048): Blender's exporter bakes nothing else.
bpy.context.scene.render.fps = 120
bpy.context.scene.render.fps_base = 1.0
bpy.ops.export_scene.fbx(filepath='$work/take.fbx', bake_anim=True, add_leaf_bones=False,
                         bake_anim_simplify_factor=0.0)
" >"$work/blender.log" 2>&1 || fail "Blender's export: $(tail -5 "$work/blender.log")"
echo "take: $frames frames x 60 joints; BVH $(stat -c %s "$work/take.bvh") bytes," \
  "FBX $(stat -c %s "$work/take.fbx") bytes"

start_server "$build/server/koma_server"
time_ms() {
  local start end
  start=$(date +%s%N)
  "$@" >/dev/null 2>"$work/err" || fail "$*: $(cat "$work/err")"
  end=$(date +%s%N)
  echo $(((end - start) / 1000000))
}
fbx_times=() bvh_times=() ratios=()
for round in $(seq 1 "$rounds"); do
  if [ $((round % 2)) = 1 ]; then
    f=$(time_ms "$koma" skeletal "$work/take.fbx" -o "$work/out.fbx" --server "$target" -q)
    b=$(time_ms "$koma" skeletal "$work/take.bvh" -o "$work/out.bvh" --send-file --server "$target" -q)
  else
    b=$(time_ms "$koma" skeletal "$work/take.bvh" -o "$work/out.bvh" --send-file --server "$target" -q)
    f=$(time_ms "$koma" skeletal "$work/take.fbx" -o "$work/out.fbx" --server "$target" -q)
  fi
  fbx_times+=("$f") bvh_times+=("$b") ratios+=("$(python3 -c "print($f / $b)")")
  echo "round $round: fbx $f ms, bvh $b ms, fbx/bvh $(python3 -c "print(round($f / $b, 3))")"
done
stop_server
[ -n "${KEEP_TAKE:-}" ] && cp "$work/take.fbx" "$work/take.bvh" "$KEEP_TAKE"
python3 - "${fbx_times[*]}" "${bvh_times[*]}" "${ratios[*]}" <<'PY'
import statistics, sys
f, b, r = ([float(x) for x in a.split()] for a in sys.argv[1:4])
print("median: fbx %.0f ms, bvh %.0f ms, ratio fbx/bvh %.3f (rounds %d)" % (
    statistics.median(f), statistics.median(b), statistics.median(r), len(r)))
PY

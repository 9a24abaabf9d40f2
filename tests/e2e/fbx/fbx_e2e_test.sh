#!/usr/bin/env bash
# e2e (issue 43): the FBX files of tests/testdata/fbx (real ones, and the Mixamo-style rig with
# pre-rotations and pivots of make_pivot_rig.py) through `koma skeletal` and the real
# koma_server: the retimed file, the timing sheet and the summary; then Blender's own FBX
# importer reads each written file (blender_retimed_test.py), and three.js's FBXLoader under
# node (three_retimed_check.py), and Debian's assimp with pivots off (assimp_retimed_check.py),
# and every bone is where the source was at the frame the timing shows. Also: --take picks a
# take, a missing one is named, the same request twice gives the same bytes.
# Usage: fbx_e2e_test.sh KOMA_SERVER KOMA FBX_POSITIONS BLENDER TESTDATA_FBX ASSIMP_POSES
set -euo pipefail
server_bin=$1 client_bin=$2 positions_bin=$3 blender=$4 data=$5 assimp_poses=$6
source "$(dirname "$0")/../lib.sh"

start_server "$server_bin"
for name in assimp_animation_with_skeleton assimp_huesitos koma_mixamo_style_pivots; do
  cp "$data/$name.fbx" "$work/$name.fbx"
  "$client_bin" skeletal "$work/$name.fbx" -o "$work/$name.anime.fbx" \
    --timing "$work/$name.timing.csv" --server "$target" >"$work/$name.out" 2>&1 ||
    fail "koma skeletal $name.fbx: $(cat "$work/$name.out")"
  grep -q 'take "' "$work/$name.out" || fail "no take line: $(cat "$work/$name.out")"
  grep -q -- "-> $work/$name.anime.fbx" "$work/$name.out" ||
    fail "the summary does not name the written file: $(head -1 "$work/$name.out")"
  cat "$work/$name.out"
  "$client_bin" skeletal "$work/$name.fbx" -o "$work/$name.again.fbx" --server "$target" -q ||
    fail "second call"
  cmp -s "$work/$name.anime.fbx" "$work/$name.again.fbx" || fail "$name: not the same bytes twice"
  rm "$work/$name.again.fbx"
done
# Maya's three animation layers: the base layer is read and rewritten, and the answer says so.
"$client_bin" skeletal "$data/ufbx_maya_anim_layers_7500_binary.fbx" -o "$work/maya.fbx" \
  --server "$target" >"$work/maya.out" 2>&1 || fail "the Maya file: $(cat "$work/maya.out")"
grep -q 'warning    fbx: take "Take 001" has 3 animation layers; koma read and retimed the base layer only' \
  "$work/maya.out" || fail "no layer warning: $(cat "$work/maya.out")"
rm -f "$work/maya.fbx" "$work/maya.out"  # not one of the files Blender compares
expect_error 1 'fbx_take: take "Nope": not in the file (it has "Armature|Action")' \
  "$client_bin" skeletal "$work/assimp_huesitos.fbx" --take Nope -o "$work/x.fbx" \
  --server "$target"
"$client_bin" skeletal "$work/assimp_huesitos.fbx" --take "Armature|Action" \
  -o "$work/named.fbx" --server "$target" -q || fail "--take with the take's name"
rm "$work/named.fbx"
# The rate options reach a file request (glTF and FBX alike): --preset twos asks for 12.
for file in "$data/assimp_huesitos.fbx" "$(dirname "$0")/../../../samples/wave.glb"; do
  out=$work/twos.${file##*.}
  "$client_bin" skeletal "$file" -o "$out" --preset twos --server "$target" >"$work/twos.out" ||
    fail "--preset twos on $file"
  grep -q "asked for 12 drawings" "$work/twos.out" || fail "$file: --preset twos: $(cat "$work/twos.out")"
  rm -f "$out"
done
stop_server
"$blender" -b --factory-startup --python-exit-code 1 \
  --python "$(dirname "$0")/blender_retimed_test.py" -- "$positions_bin" "$work" 2>&1 |
  grep -v '^$' | tee "$work/blender.out" | grep -v "^FBX version\|^Blender\|^Read\|^Blender quit" || true
grep -q "retimed fbx against Blender: PASS" "$work/blender.out" ||
  fail "Blender's check: $(tail -5 "$work/blender.out")"
three=$(dirname "$0")/../gltf/three_fbx_poses.mjs
[ -d "$(dirname "$0")/../gltf/node_modules/three" ] ||
  fail "three.js is not installed in tests/e2e/gltf/node_modules: run ./scripts/install-deps.sh"
# three.js is not asked about the Mixamo-style file: its tracks animate a node as if it had no
# rotation or scaling pivot or offset (the position is Lcl Translation alone), and where one
# axis of a channel has a key and another has none, it holds that axis's previous key instead
# of interpolating, so it reads neither the source nor koma's reading of it (Blender does).
python3 "$(dirname "$0")/three_retimed_check.py" "$positions_bin" "$three" "$work" \
  --skip koma_mixamo_style_pivots || fail "three.js's check"
# assimp 5.2 with pivots off leaves a node with pivots or offsets at rest (its animation goes
# to $AssimpFbx$ helper nodes it makes only with pivots on): on that file, what it shows of the
# written file is compared with what it shows of the source.
[ -x "$assimp_poses" ] ||
  fail "no assimp_poses ($assimp_poses): run ./scripts/install-deps.sh (libassimp-dev), then cmake"
python3 "$(dirname "$0")/assimp_retimed_check.py" "$assimp_poses" "$positions_bin" "$work" \
  --own-reading koma_mixamo_style_pivots || fail "assimp's check"
echo "fbx e2e: ok"

#!/usr/bin/env bash
# End to end, glTF: the real koma_server on a free loopback port, the real koma client on the
# bundled samples/wave.glb: GLB and .gltf in and out, standard input, --gltf-retime-none byte
# for byte, the options, usage errors and the server's errors, and `koma batch` over .glb,
# .gltf and .vrm files against the single command, byte for byte.
# Usage: gltf_cli_e2e_test.sh KOMA_SERVER KOMA SAMPLE_GLB
set -euo pipefail
server_bin=$1 client_bin=$2 sample=$3

source "$(dirname "$0")/lib.sh"

start_server "$server_bin" --worker_threads=2

koma() { "$client_bin" "$@" --server "$target" --deadline 30; }
# The same as a program, for expect_error (which runs programs, not functions).
printf '#!/bin/sh\nexec "%s" "$@" --server "%s" --deadline 30\n' "$client_bin" "$target" >"$work/koma"
chmod +x "$work/koma"

# GLB in, GLB out, with a timing sheet; the summary names the animation.
koma skeletal "$sample" -o "$work/out.glb" --timing "$work/timing.csv" >"$work/summary.txt" ||
  fail "koma skeletal on a glb failed"
cat "$work/summary.txt"
grep -q 'animation 0 "Wave": 61 frames at 30 fps from 0 s' "$work/summary.txt" ||
  fail "the summary lacks the animation line"
[ "$(head -c 4 "$work/out.glb")" = glTF ] || fail "the output is not a GLB"
[ $(($(wc -l <"$work/timing.csv") - 1)) = 61 ] || fail "the timing sheet is not 61 frames"
grep -q ",HELD," "$work/timing.csv" || fail "no HELD frame in the timing sheet"

# The written file reads back (retimed again); standard input is recognised by its content.
koma skeletal "$work/out.glb" -o "$work/again.glb" >/dev/null || fail "the output does not read back"
koma skeletal - -o "$work/stdin.glb" <"$sample" >/dev/null || fail "a glb on standard input"
cmp -s "$work/out.glb" "$work/stdin.glb" || fail "standard input gave another file"

# Nothing retimed: the same bytes.
koma skeletal "$sample" -o "$work/none.glb" --gltf-retime-none >/dev/null
cmp -s "$sample" "$work/none.glb" || fail "--gltf-retime-none changed the file"

# A .gltf with an embedded buffer: .gltf in, .gltf out (JSON text).
/usr/bin/python3 - "$sample" "$work/wave.gltf" <<'PY'
import base64, json, struct, sys
data = open(sys.argv[1], "rb").read()
length = struct.unpack("<I", data[12:16])[0]
doc = json.loads(data[20:20 + length])
bin_start = 20 + length + 8
doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
    data[bin_start:bin_start + doc["buffers"][0]["byteLength"]]).decode()
open(sys.argv[2], "w").write(json.dumps(doc, indent=1))
PY
koma skeletal "$work/wave.gltf" -o "$work/out.gltf" --gltf-keys linear >/dev/null ||
  fail "a .gltf failed"
/usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); s=d["animations"][0]["samplers"]; assert all(x["interpolation"] == "LINEAR" for x in s), s; assert d["buffers"][0]["uri"].startswith("data:")' \
  "$work/out.gltf" || fail "the .gltf output is not LINEAR keys with an embedded buffer"

# Keep the original beside the retimed one.
koma skeletal "$sample" -o "$work/both.vrm" --gltf-keep-original --animation Wave >/dev/null
/usr/bin/python3 - "$work/both.vrm" <<'PY' || fail "--gltf-keep-original did not add Wave.anime"
import json, struct, sys
data = open(sys.argv[1], "rb").read()
doc = json.loads(data[20:20 + struct.unpack("<I", data[12:16])[0]])
names = [a["name"] for a in doc["animations"]]
assert names == ["Wave", "Wave.anime"], names
assert doc["extensions"]["VRMC_vrm"]["meta"]["name"] == "wave"
PY

# Usage errors (exit 2) and the server's errors (exit 1).
expect_error 2 "the input is a GLB file" "$work/koma" skeletal "$sample" -o "$work/x.gltf"
expect_error 2 "the input is BVH" \
  "$work/koma" skeletal "$(dirname "$sample")/pitch.bvh" -o "$work/x.glb"
expect_error 2 "are for glTF inputs" \
  "$work/koma" skeletal "$(dirname "$sample")/pitch.bvh" -o "$work/x.bvh" --gltf-keys linear
expect_error 1 'INVALID_ARGUMENT: gltf_animations\[0\]: "Run" is neither' \
  "$work/koma" skeletal "$sample" -o "$work/x.glb" --animation Run
head -c 300 "$sample" >"$work/cut.glb"
expect_error 1 "INVALID_ARGUMENT: gltf: GLB header: length" "$work/koma" skeletal "$work/cut.glb" -o "$work/x.glb"
expect_error 1 "is a glTF file, not motion3.json or CSV" "$work/koma" curves "$sample" -o "$work/x.json"
[ ! -e "$work/x.glb" ] || fail "a failed call wrote an output"

# koma batch over .glb, .vrm and .gltf: each output byte for byte the single command's.
mkdir -p "$work/in/sub"
cp "$sample" "$work/in/a.glb"
cp "$sample" "$work/in/sub/b.vrm"
cp "$work/wave.gltf" "$work/in/c.gltf"
"$client_bin" batch skeletal "$work/in" -o "$work/batch" --timing --omit 5 --server "$target" \
  --quiet || fail "koma batch over glTF files failed"
for name in a.glb sub/b.vrm c.gltf; do
  koma skeletal "$work/in/$name" -o "$work/single.${name##*.}" --omit 5 >/dev/null
  cmp -s "$work/batch/$name" "$work/single.${name##*.}" || fail "batch $name differs from koma skeletal"
done
ls "$work/batch/"*timing.csv >/dev/null || fail "batch wrote no timing sheet"

stop_server
echo "gltf cli e2e: OK"

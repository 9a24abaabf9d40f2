# Run by Blender (`blender -b --factory-startup --python blender_poses.py -- IN.glb FPS OUT.json
# FRAMES`): imports a glTF file with Blender's glTF importer (io_scene_gltf2) at FPS frames per
# second and writes, for each listed frame k (counted from the animation's first key), the
# world head of every bone and every shape key's value, as JSON {"k": {"bones": {name: [x, y,
# z]}, "keys": {name: value}}}. FRAMES: comma-separated frame numbers.
import json
import sys

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still uses numpy's `np.bool`, which Debian 12's numpy 1.24
# removed; it was only an alias of the builtin.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

argv = sys.argv[sys.argv.index("--") + 1:]
path, fps, out_path = argv[0], int(argv[1]), argv[2]
frames = [int(f) for f in argv[3].split(",")]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = fps
scene.render.fps_base = 1.0
bpy.ops.import_scene.gltf(filepath=path)

armatures = [o for o in scene.objects if o.type == "ARMATURE"]
meshes = [o for o in scene.objects if o.type == "MESH" and o.data.shape_keys]
first = None
for o in armatures + meshes:
    holder = o.data.shape_keys if o.type == "MESH" else o
    action = holder.animation_data.action if holder.animation_data else None
    if action is not None:
        start = action.frame_range[0]
        first = start if first is None else min(first, start)
first = round(first or 0)

poses = {}
for k in frames:
    scene.frame_set(first + k)
    bones = {}
    for armature in armatures:
        for bone in armature.pose.bones:
            head = armature.matrix_world @ bone.head
            bones[bone.name] = [head.x, head.y, head.z]
    keys = {}
    for mesh in meshes:
        for block in mesh.data.shape_keys.key_blocks[1:]:
            keys[mesh.name + "/" + block.name] = block.value
    poses[str(k)] = {"bones": bones, "keys": keys}
with open(out_path, "w") as f:
    json.dump({"first_frame": first, "poses": poses}, f)
print("poses", len(poses), "first frame", first)

# Run by Blender (`blender -b --factory-startup --python blender_export.py -- IN.bvh OUT.glb
# [morph]`): imports a BVH with Blender's own importer and writes it as glTF with Blender's
# glTF exporter (io_scene_gltf2), GLB or embedded .gltf by OUT's extension. With "morph", a mesh
# skinned to the root bone gets two shape keys animated over the clip, so the file has a skin,
# morph targets and a weights channel like a character's face.
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
bvh_path, out_path = argv[0], argv[1]
morph = len(argv) > 2 and argv[2] == "morph"

bpy.ops.wm.read_factory_settings(use_empty=True)
# Debian's Blender 3.4 BVH importer opens the file with mode 'rU', which Python 3.11 refuses;
# the same open without the obsolete 'U' (universal newlines are the default).
import builtins  # noqa: E402

import io_anim_bvh.import_bvh as import_bvh  # noqa: E402

import_bvh.open = lambda path, mode="r", *a, **k: builtins.open(path, mode.replace("U", ""), *a, **k)
bpy.ops.import_anim.bvh(filepath=bvh_path, update_scene_fps=True, update_scene_duration=True)
armature = bpy.context.view_layer.objects.active
scene = bpy.context.scene
# The importer never shortens the scene (250 frames by default): end it at the clip's end.
scene.frame_end = int(armature.animation_data.action.frame_range[1])

if morph:
    root = armature.data.bones[0].name
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    body = bpy.context.view_layer.objects.active
    body.name = "Face"
    body.shape_key_add(name="Basis")
    for name, axis in (("smile", 0), ("blink", 2)):
        key = body.shape_key_add(name=name)
        for point in key.data:
            point.co[axis] *= 1.5
    keys = body.data.shape_keys.key_blocks
    start, end = scene.frame_start, scene.frame_end
    for frame, smile, blink in ((start, 0.0, 1.0), ((start + end) // 2, 1.0, 0.0), (end, 0.2, 0.6)):
        keys["smile"].value = smile
        keys["blink"].value = blink
        keys["smile"].keyframe_insert("value", frame=frame)
        keys["blink"].keyframe_insert("value", frame=frame)
    group = body.vertex_groups.new(name=root)
    group.add([v.index for v in body.data.vertices], 1.0, "REPLACE")
    modifier = body.modifiers.new("Armature", "ARMATURE")
    modifier.object = armature
    body.parent = armature

fmt = "GLB" if out_path.lower().endswith(".glb") else "GLTF_EMBEDDED"
bpy.ops.export_scene.gltf(filepath=out_path, export_format=fmt, export_animations=True,
                          export_morph=True, export_skins=True, export_force_sampling=True,
                          export_nla_strips=False)
print("exported", out_path, "fps", scene.render.fps)

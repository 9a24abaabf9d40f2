"""Shared by the headless Blender tests (addon_test.py, addon_zip_test.py): koma_server on
loopback, a keyed armature, the timing map koma gives for it sampled independently, and the
checks of the add-on's "<name>.anime" action.
"""
import math
import os
import signal
import subprocess
import time

import bpy


def start_server(server_bin, workdir):
    port_file = os.path.join(workdir, "port")
    process = subprocess.Popen([server_bin, "--address=127.0.0.1:0", f"--port_file={port_file}",
                                "--log_level=warn", "--shutdown_delay_ms=0"])
    deadline = time.monotonic() + 20
    while not (os.path.exists(port_file) and open(port_file).read().strip()):
        assert process.poll() is None, "koma_server exited"
        assert time.monotonic() < deadline, "koma_server did not start within 20 s"
        time.sleep(0.02)
    return process, f"127.0.0.1:{open(port_file).read().strip()}"


def stop_server(process):
    process.send_signal(signal.SIGTERM)
    try:
        process.wait(timeout=20)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout=5)


def make_armature(name, frames, fps):
    """A 3-bone chain whose action "<name>" is keyed on every frame 1..frames."""
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = fps, 1.0
    data = bpy.data.armatures.new(name)
    obj = bpy.data.objects.new(name, data)
    scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    parent = None
    for i, bone_name in enumerate(("Root", "Arm", "Hand")):
        bone = data.edit_bones.new(bone_name)
        bone.head, bone.tail = (0, 0, i), (0, 0, i + 1)
        bone.parent = parent
        bone.use_connect = parent is not None
        parent = bone
    bpy.ops.object.mode_set(mode="OBJECT")
    root, arm = obj.pose.bones["Root"], obj.pose.bones["Arm"]
    arm.rotation_mode = "XYZ"
    for frame in range(1, frames + 1):
        s = (frame - 1) / (frames - 1)
        eased = s * s * (3 - 2 * s)  # slow, fast, slow
        root.location = (0.02 * frame, 0, 0)
        arm.rotation_euler = (math.radians(150 * eased), 0, 0)
        root.keyframe_insert("location", frame=frame)
        arm.keyframe_insert("rotation_euler", frame=frame)
    obj.animation_data.action.name = name
    scene.frame_start, scene.frame_end = 1, frames
    return obj


def expected_source_frames(obj, address, **options):
    """The timing map koma gives for the bones' world heads, sampled here on its own."""
    import koma  # on sys.path once the add-on has imported it from its package folder
    scene = bpy.context.scene
    names = [b.name for b in obj.pose.bones]
    parents = [names.index(b.parent.name) if b.parent else -1 for b in obj.pose.bones]
    start, end = (int(round(f)) for f in obj.animation_data.action.frame_range)
    values = []
    for frame in range(start, end + 1):
        scene.frame_set(frame)
        evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
        for b in evaluated.pose.bones:
            values.extend(evaluated.matrix_world @ b.head)
    fps = scene.render.fps / scene.render.fps_base
    with koma.Client(address, timeout=30) as client:
        return client.retime_skeletal(koma.Positions(names, parents, 1 / fps, values),
                                      **options)


def check_anime_action(obj, source, expected):
    anime = obj.animation_data.action
    assert anime.name == source.name + ".anime", anime.name
    assert source.use_fake_user, "the original action must be kept"
    frames = expected.source_frames
    assert list(anime["koma_source_frames"]) == frames
    start = int(round(source.frame_range[0]))
    assert len(anime.fcurves) == len(source.fcurves) > 0
    for out in anime.fcurves:
        curve = source.fcurves.find(out.data_path, index=out.array_index)
        assert curve is not None, out.data_path
        points = out.keyframe_points
        assert len(points) == len(frames), (out.data_path, len(points))
        for t, point in enumerate(points):
            assert point.interpolation == "CONSTANT", (out.data_path, t)
            assert point.co.x == start + t, (out.data_path, t, point.co.x)
            want = curve.evaluate(start + frames[t])
            assert abs(point.co.y - want) <= 1e-6 * max(1.0, abs(want)), (out.data_path, t)
            # Held drawings: between keys the value stays the key's.
            if t + 1 < len(points):
                assert abs(out.evaluate(start + t + 0.5) - point.co.y) <= 1e-6 * max(1.0, abs(want))


def run_operator(settings_values):
    settings = bpy.context.scene.koma
    for key, value in settings_values.items():
        setattr(settings, key, value)
    return bpy.ops.koma.retime_action()

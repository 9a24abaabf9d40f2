"""Headless Blender test of the koma add-on against the real koma_server on loopback.

    blender -b --factory-startup --python-exit-code 1 --python addon_test.py -- \
        KOMA_SERVER ADDON_PARENT_DIR KOMA_PYTHON_DIR

Enables the add-on through addon_utils with its "koma package folder" preference set (koma
itself is not on Blender's path), builds an armature with a keyed action (an arm swinging slow-fast-slow while the root
travels), runs the add-on's operator, and checks the new action "<name>.anime": every output
frame keyed, CONSTANT interpolation, each key the source pose the timing map names; the map
is the one koma answers for the same bone positions sampled here independently. Once at
24 fps (no grid) and once for a 120 fps action on the 24 fps film grid. Then a wrong server
address: the operator cancels with koma's error and writes nothing.
"""
import math
import os
import signal
import subprocess
import sys
import tempfile
import time

import bpy

import addon_utils

server_bin, addon_parent, package_dir = sys.argv[sys.argv.index("--") + 1:][:3]
# The add-on is found on sys.path; `koma` is not: the add-on finds it through its preference.
sys.path.insert(0, addon_parent)


def start_server(workdir):
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


def main():
    # Enabled as a user would (bl_info, register, preferences), pointed at the built package.
    assert addon_utils.enable("koma_retime", default_set=True) is not None
    bpy.context.preferences.addons["koma_retime"].preferences.package_folder = package_dir
    workdir = tempfile.mkdtemp(prefix="koma-blender-")
    process, address = start_server(workdir)
    try:
        # 48 frames at 24 fps, counted in frames (timing rate 0): omissions and holds.
        obj = make_armature("swing", 48, 24)
        source = obj.animation_data.action
        result = run_operator({"server": address, "omissions": 3, "holds": -1, "max_hold": 3,
                               "timing_fps": 0.0})
        assert result == {"FINISHED"}, result
        obj.animation_data.action = source  # sample the source again, independently
        expected = expected_source_frames(obj, address, omissions=3, max_hold=3, timing_fps=0,
                                          return_motion=False)
        obj.animation_data.action = bpy.data.actions[source.name + ".anime"]
        assert expected.counts["omissions_applied"] == 3 and expected.deleted_frames, \
            expected.counts
        assert expected.counts["holds_applied"] > 0
        check_anime_action(obj, source, expected)
        print(f"24 fps: {expected.counts}")

        # A 120 fps action on the 24 fps film grid (the panel's default rate).
        obj120 = make_armature("swing120", 120, 120)
        source120 = obj120.animation_data.action
        bpy.context.view_layer.objects.active = obj120
        expected120 = expected_source_frames(obj120, address, max_hold=3, timing_fps=24.0,
                                             return_motion=False)
        assert expected120.timing_fps == 24
        runs = 1 + sum(1 for a, b in zip(expected120.source_frames,
                                         expected120.source_frames[1:]) if a != b)
        assert runs <= 24, runs  # at most one drawing per grid frame (5 source frames)
        result = run_operator({"server": address, "omissions": -1, "holds": -1, "max_hold": 3,
                               "timing_fps": 24.0, "preset": "PAPER"})
        assert result == {"FINISHED"}, result
        check_anime_action(obj120, source120, expected120)
        print(f"120 fps on the 24 fps grid: {runs} drawings, {expected120.counts}")

        # The panel's "On threes" preset: 8 drawings a second, a median hold of 3 grid frames
        # (docs/semantics.md, "Drawing rate"), as the Python client asked the same way.
        obj120.animation_data.action = source120
        expected_threes = expected_source_frames(obj120, address, drawings_per_second=8.0,
                                                 timing_fps=24.0, output_rate="TIMING_RATE",
                                                 return_motion=False)
        grid_runs = []
        for t, frame in enumerate(expected_threes.source_frames):
            if t == 0 or frame != expected_threes.source_frames[t - 1]:
                grid_runs.append(0)
            grid_runs[-1] += 1
        grid_runs.sort()
        assert grid_runs[(len(grid_runs) - 1) // 2] == 3, grid_runs
        expected_threes = expected_source_frames(obj120, address, drawings_per_second=8.0,
                                                 timing_fps=24.0, return_motion=False)
        result = run_operator({"server": address, "omissions": -1, "holds": -1, "max_hold": 0,
                               "preset": "THREES", "timing_fps": 24.0})
        assert result == {"FINISHED"}, result
        check_anime_action(obj120, source120, expected_threes)
        print(f"on threes: {len(grid_runs)} drawings on the grid, {expected_threes.counts}")

        # No server there: the operator reports koma's error and changes nothing.
        actions_before = len(bpy.data.actions)
        bpy.context.view_layer.objects.active = obj
        obj.animation_data.action = source
        try:
            result = run_operator({"server": "127.0.0.1:1", "timeout": 5.0})
            assert result == {"CANCELLED"}, result
        except RuntimeError as error:  # bpy.ops raises on an ERROR report
            assert "UNAVAILABLE" in str(error), error
        assert len(bpy.data.actions) == actions_before
        assert obj.animation_data.action == source
    finally:
        stop_server(process)
    print("koma Blender add-on test: PASS")


main()

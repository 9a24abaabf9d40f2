"""The add-on's file mode (KOMA_OT_retime_file), run by addon_test.py against the real
koma_server: for a real FBX (tests/testdata/fbx/assimp_huesitos.fbx), GLB (samples/wave.glb) and
BVH (samples/pitch.bvh), each copied into a scratch folder, the operator writes the retimed file
(next to the source, or where the panel's Output says) with the bytes `koma skeletal FILE -o OUT`
and koma.Client.retime_skeletal write for the same options, and imports it with Blender's own
importer; the imported armature's action is checked against the source imported by the same
importer: every output frame shows the source's pose at the timing map's source frame (FBX and
BVH: a key on every output frame; glTF: a CONSTANT key where each drawing starts), held frames
repeat the frame before, and the panel's summary names the frames, drawings, omissions and take.
Then the errors: no server, an unreadable file, a file the server refuses, a take not in the
file, a take for a BVH, a file of another kind; each an operator report, never a traceback, and
nothing written or imported.
"""
import builtins
import json
import os
import shutil
import subprocess

import bpy


def _import_source(path, kind, fps=None):
    """The source file imported by Blender's importer for its kind: (armature, action)."""
    before = set(bpy.data.objects)
    if kind == "fbx":
        assert bpy.ops.import_scene.fbx(filepath=path) == {"FINISHED"}
    elif kind == "glb":
        import numpy
        if "bool" not in vars(numpy):  # Debian's Blender 3.4 importer and numpy 1.24
            numpy.bool = bool
        scene = bpy.context.scene
        scene.render.fps, scene.render.fps_base = round(fps), round(fps) / fps
        assert bpy.ops.import_scene.gltf(filepath=path) == {"FINISHED"}
    else:
        from io_anim_bvh import import_bvh  # Debian's Blender 3.4 opens with 'rU'
        import_bvh.open = lambda p, mode="r", *a, **k: builtins.open(p, mode.replace("U", ""),
                                                                      *a, **k)
        try:
            assert bpy.ops.import_anim.bvh(filepath=path, update_scene_fps=True) == {"FINISHED"}
        finally:
            del import_bvh.open
    armatures = [o for o in bpy.data.objects if o not in before and o.type == "ARMATURE"]
    assert len(armatures) == 1, armatures
    return armatures[0], armatures[0].animation_data.action


def _cli(cli, address, source, out, flags):
    run = subprocess.run([cli, "skeletal", source, "-o", out, "--server", address, "--json",
                          "-q"] + flags, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    with open(out, "rb") as f:
        return f.read(), json.loads(run.stdout)


def _run(settings_values):
    settings = bpy.context.scene.koma
    for name in settings.bl_rna.properties.keys():
        if name not in ("rna_type", "server"):
            settings.property_unset(name)
    for key, value in settings_values.items():
        setattr(settings, key, value)
    before = set(bpy.data.objects)
    result = bpy.ops.koma.retime_file()
    return result, [o for o in bpy.data.objects if o not in before]


def _expect_error(settings_values, *needles):
    """The operator cancels with an ERROR report holding every needle; nothing imported."""
    objects = len(bpy.data.objects)
    try:
        result, _ = _run(settings_values)
        raise AssertionError(f"expected an error report, got {result}")
    except RuntimeError as error:  # bpy.ops raises on an ERROR report
        message = str(error)
    assert "Traceback" not in message and "Error: Python" not in message, message
    for needle in needles:
        assert needle in message, (needle, message)
    assert len(bpy.data.objects) == objects
    assert bpy.context.scene.koma.last_summary in message, bpy.context.scene.koma.last_summary
    print(f"error as expected: {message.strip()}")
    return message


def _values(action, frame):
    return {(c.data_path, c.array_index): c.evaluate(frame) for c in action.fcurves}


def _check_imported(kind, armature, source_action, frames, first_frame):
    """The imported retimed action against the source's import at the timing's source frames."""
    action = armature.animation_data.action
    assert list(action["koma_source_frames"]) == frames
    curves = list(action.fcurves)
    assert curves and len(curves) == len(source_action.fcurves), (len(curves),
                                                                   len(source_action.fcurves))
    starts = [t for t, f in enumerate(frames) if t == 0 or f != frames[t - 1]]
    for curve in curves:
        keys = [k.co.x - first_frame for k in curve.keyframe_points]
        if kind == "glb":  # STEP keys: one where each drawing starts, CONSTANT between
            assert [round(x) for x in keys] == starts, (curve.data_path, keys)
            assert all(abs(x - round(x)) < 1e-3 for x in keys), keys
            assert all(k.interpolation == "CONSTANT" for k in curve.keyframe_points)
        else:  # a key on every output frame
            assert keys == list(range(len(frames))), (curve.data_path, keys[:5], len(keys))
    scale = max(1.0, max(abs(v) for f in set(frames)
                         for v in _values(source_action, first_frame + f).values()))
    moving, worst = 0, 0.0
    previous = None
    for t, f in enumerate(frames):
        mine = _values(action, first_frame + t)
        theirs = _values(source_action, first_frame + f)
        assert mine.keys() == theirs.keys()
        worst = max(worst, max(abs(mine[k] - theirs[k]) for k in mine))
        if previous is not None:
            change = max(abs(mine[k] - previous[k]) for k in mine)
            if f == frames[t - 1]:
                assert change <= 1e-6 * scale, (t, change)  # a held frame repeats the drawing
            elif change > 1e-4 * scale:
                moving += 1
        previous = mine
    assert worst <= 1e-4 * scale, (kind, worst, scale)
    # The source moves: (nearly) every new drawing shows a new pose.
    assert moving >= 0.8 * (len(starts) - 1) and moving > 0, (moving, len(starts))
    return len(starts), worst


def check_file_mode(address, cli, source_dir, workdir):
    import koma
    folder = os.path.join(workdir, "files")
    os.makedirs(os.path.join(folder, "chosen"))
    cases = [
        # (source, panel settings, the same options for the CLI and for the Python package)
        ("tests/testdata/fbx/assimp_huesitos.fbx", {}, [], {}),
        ("samples/wave.glb", {"preset": "TWOS", "omissions": 2,
                              "output_file": os.path.join(folder, "chosen", "waved.glb")},
         ["--preset", "twos", "--omit", "2"], {"preset": "twos", "omissions": 2}),
        ("samples/pitch.bvh", {"timing_fps": 0.0, "max_hold": 2, "holds": 20},
         ["--timing-fps", "0", "--max-hold", "2", "--hold", "20"],
         {"timing_fps": 0, "max_hold": 2, "holds": 20}),
    ]
    for relative, panel, flags, options in cases:
        name = os.path.basename(relative)
        stem, ext = os.path.splitext(name)
        kind = ext[1:]
        source = os.path.join(folder, name)
        shutil.copyfile(os.path.join(source_dir, relative), source)
        written = panel.get("output_file") or os.path.join(folder, stem + ".anime" + ext)
        result, new = _run(dict(panel, motion_file=source))
        assert result == {"FINISHED"}, result
        summary = bpy.context.scene.koma.last_summary

        with open(written, "rb") as f:
            mine = f.read()
        cli_bytes, cli_summary = _cli(cli, address, source,
                                      os.path.join(folder, f"cli_{stem}{ext}"), flags)
        assert mine == cli_bytes, f"{name}: the add-on's file differs from the CLI's"
        with koma.Client(address, timeout=60) as client:
            expected = client.retime_skeletal(source, **options)
        assert mine == expected.output_bytes, f"{name}: the add-on's file differs from Python's"
        frames = expected.source_frames

        armatures = [o for o in new if o.type == "ARMATURE"]
        assert len(armatures) == 1, new
        armature = armatures[0]
        assert bpy.context.view_layer.objects.active == armature
        fps = expected.animations[0]["source_fps"] if expected.animations else None
        source_armature, source_action = _import_source(source, kind, fps)
        first = 0 if kind == "glb" else 1  # the glTF importer keys from frame 0
        drawings, worst = _check_imported(kind, armature, source_action, frames, first)
        assert drawings == cli_summary["drawings_shown"], (drawings, cli_summary)
        assert cli_summary["output_frames"] == len(frames)
        assert f"{len(frames)} frames, {drawings} drawings, omitted " \
               f"{cli_summary['omissions_applied']}, held {cli_summary['holds_applied']}" \
               in summary, summary
        assert os.path.basename(written) in summary and armature.name in summary, summary
        if kind == "fbx":
            assert f'take "{expected.take["name"]}"' in summary, summary
        if kind == "glb":
            assert f'animations "{expected.animations[0]["name"]}"' in summary, summary
        print(f"file mode {name}: {summary} (worst difference from the source {worst:.2g})")
        for obj in (source_armature, armature):
            obj.animation_data.action = None
        bpy.ops.object.select_all(action="DESELECT")

    fbx = os.path.join(folder, "assimp_huesitos.fbx")
    anime_fbx = os.path.join(folder, "assimp_huesitos.anime.fbx")
    default_bytes = open(anime_fbx, "rb").read()
    # The take by name: the file's current take, so the same bytes.
    os.remove(anime_fbx)
    result, _ = _run({"motion_file": fbx, "take": "Armature|Action"})
    assert result == {"FINISHED"} and open(anime_fbx, "rb").read() == default_bytes

    # Errors: a report, nothing written or imported.
    os.remove(anime_fbx)
    _expect_error({"motion_file": fbx, "server": "127.0.0.1:1", "timeout": 5.0},
                  "koma: UNAVAILABLE")
    bpy.context.scene.koma.server = address
    assert not os.path.exists(anime_fbx)
    _expect_error({"motion_file": os.path.join(folder, "missing.fbx")}, "cannot read",
                  "missing.fbx")
    ascii_fbx = os.path.join(folder, "ascii.fbx")
    with open(ascii_fbx, "w") as f:
        f.write("; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n}\n")
    _expect_error({"motion_file": ascii_fbx}, "koma: INVALID_ARGUMENT: fbx: ", "ASCII")
    _expect_error({"motion_file": fbx, "take": "nope"}, "koma: INVALID_ARGUMENT: fbx_take: ",
                  "nope")
    _expect_error({"motion_file": os.path.join(folder, "pitch.bvh"), "take": "x"},
                  "a BVH file has one take")
    text = os.path.join(folder, "notes.txt")
    open(text, "w").write("x")
    _expect_error({"motion_file": text}, "not a motion file")
    _expect_error({"motion_file": ""}, "choose a motion file")
    for stem in ("ascii", "missing", "notes"):
        assert not [f for f in os.listdir(folder) if f.startswith(stem + ".anime")], stem
    assert not os.path.exists(anime_fbx)
    shutil.rmtree(folder)

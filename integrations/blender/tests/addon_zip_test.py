"""Headless Blender test of the add-on's installable zip, against the real koma_server.

    BLENDER_USER_SCRIPTS=EMPTY_DIR blender -b --factory-startup --python-exit-code 1 \
        --python addon_zip_test.py -- KOMA_SERVER ADDON_ZIP VERSION

(addon_zip_test.sh makes the folder and removes it.) Installs the zip as a user does, through
Blender's own installer (bpy.ops.preferences.addon_install, what Preferences > Add-ons >
Install runs), into the user scripts folder; enables it (bpy.ops.preferences.addon_enable); with
no package folder set and no $KOMA_PYTHONPATH, retimes a keyed armature's action and checks
the "<name>.anime" action against the timing map koma answers for the same positions; then the
file mode on a real FBX (the same panel options): the written file against koma.Client's bytes,
imported by Blender's FBX importer. The koma package used must be the zip's copy, installed
under the user scripts folder, at the project's version; only grpcio and protobuf come from
Blender's Python.
"""
import os
import shutil
import sys
import tempfile

import bpy

server_bin, addon_zip, version = sys.argv[sys.argv.index("--") + 1:][:3]
_SOURCE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_test_helpers import (check_anime_action, expected_source_frames,  # noqa: E402
                                  make_armature, run_operator, start_server, stop_server)


def main():
    user_scripts = os.environ["BLENDER_USER_SCRIPTS"]
    assert "KOMA_PYTHONPATH" not in os.environ
    assert "koma" not in sys.modules and "koma_retime" not in sys.modules

    result = bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
    assert result == {"FINISHED"}, result
    installed = os.path.join(user_scripts, "addons", "koma_retime")
    for part in ("__init__.py", "bundled/koma/__init__.py", "bundled/koma/v1/retime_pb2_grpc.py"):
        assert os.path.isfile(os.path.join(installed, part)), f"the installer left no {part}"
    result = bpy.ops.preferences.addon_enable(module="koma_retime")
    assert result == {"FINISHED"}, result
    assert "koma_retime" in bpy.context.preferences.addons
    assert bpy.context.preferences.addons["koma_retime"].preferences.package_folder == ""
    assert tuple(sys.modules["koma_retime"].bl_info["version"]) == \
        tuple(int(p) for p in version.split("."))

    workdir = tempfile.mkdtemp(prefix="koma-blender-zip-")
    process, address = start_server(server_bin, workdir)
    try:
        obj = make_armature("zipswing", 36, 24)
        source = obj.animation_data.action
        result = run_operator({"server": address, "omissions": 2, "holds": -1, "max_hold": 3,
                               "timing_fps": 0.0})
        assert result == {"FINISHED"}, result
        import koma  # the operator imported it: it must be the zip's
        where = os.path.realpath(koma.__file__)
        assert where.startswith(os.path.realpath(installed) + os.sep), where
        assert koma.__version__ == version, koma.__version__
        anime = obj.animation_data.action
        obj.animation_data.action = source
        expected = expected_source_frames(obj, address, omissions=2, max_hold=3, timing_fps=0,
                                          return_motion=False)
        obj.animation_data.action = anime
        assert expected.counts["omissions_applied"] == 2, expected.counts
        check_anime_action(obj, source, expected)
        print(f"installed from {os.path.basename(addon_zip)}; koma {koma.__version__} from "
              f"{os.path.dirname(where)}; {expected.counts}")

        # The file mode with the zip's package: a real FBX retimed, written next to it with
        # the bytes koma.Client gives, and imported by Blender's FBX importer.
        fbx = os.path.join(workdir, "huesitos.fbx")
        shutil.copyfile(os.path.join(_SOURCE_DIR, "tests", "testdata", "fbx",
                                     "assimp_huesitos.fbx"), fbx)
        bpy.context.scene.koma.motion_file = fbx
        before = set(bpy.data.objects)
        assert bpy.ops.koma.retime_file() == {"FINISHED"}
        with koma.Client(address, timeout=30) as client:
            want = client.retime_skeletal(fbx, timing_fps=0, omissions=2, max_hold=3)
        with open(os.path.join(workdir, "huesitos.anime.fbx"), "rb") as f:
            assert f.read() == want.output_bytes, "the file mode's FBX differs from koma.Client's"
        imported = [o for o in bpy.data.objects if o not in before and o.type == "ARMATURE"]
        assert len(imported) == 1, imported
        keys = {len(c.keyframe_points) for c in imported[0].animation_data.action.fcurves}
        assert keys == {len(want.source_frames)}, keys
        print(f"file mode: {bpy.context.scene.koma.last_summary}")
    finally:
        stop_server(process)
    print("koma Blender add-on zip test: PASS")


main()

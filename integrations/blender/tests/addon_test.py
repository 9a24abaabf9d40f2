"""Headless Blender test of the koma add-on against the real koma_server on loopback.

    blender -b --factory-startup --python-exit-code 1 --python addon_test.py -- \
        KOMA_SERVER ADDON_PARENT_DIR KOMA_PYTHON_DIR KOMA_CLI SOURCE_DIR

Enables the add-on through addon_utils with its "koma package folder" preference set (koma
itself is not on Blender's path), builds an armature with a keyed action (an arm swinging slow-fast-slow while the root
travels), runs the add-on's operator, and checks the new action "<name>.anime": every output
frame keyed, CONSTANT interpolation, each key the source pose the timing map names; the map
is the one koma answers for the same bone positions sampled here independently. Once at
24 fps (no grid), once for a 120 fps action on the 24 fps film grid (the paper's counts, then
on threes), and once with the panel's defaults (the server's anime timing). Then a wrong
server address: the operator cancels with koma's error and writes nothing. Then "Apply
X-sheet" (xsheet_checks.py): edited sheets on an action, frame by frame. Then the file
mode (file_mode_checks.py): real FBX, GLB and BVH files retimed, written with the CLI's bytes,
imported and checked against the source; and its errors.
"""
import os
import sys
import tempfile

import bpy

import addon_utils

server_bin, addon_parent, package_dir, cli_bin, source_dir = \
    sys.argv[sys.argv.index("--") + 1:][:5]
# The add-on is found on sys.path; `koma` is not: the add-on finds it through its preference.
sys.path.insert(0, addon_parent)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_test_helpers import (check_anime_action, expected_source_frames,  # noqa: E402
                                  make_armature, run_operator, start_server, stop_server)
from file_mode_checks import check_file_mode  # noqa: E402
from xsheet_checks import check_xsheet  # noqa: E402


def main():
    # Enabled as a user would (bl_info, register, preferences), pointed at the built package.
    assert addon_utils.enable("koma_retime", default_set=True) is not None
    bpy.context.preferences.addons["koma_retime"].preferences.package_folder = package_dir
    workdir = tempfile.mkdtemp(prefix="koma-blender-")
    process, address = start_server(server_bin, workdir)
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
        bpy.data.actions.remove(bpy.data.actions[source120.name + ".anime"])  # the last run's
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

        # The panel as a new scene has it: the server's anime defaults (docs/semantics.md,
        # "Defaults: anime timing"), on a 5 s take at 30 fps: on threes or so, and snaps that
        # scale with the take (at least one every two seconds).
        settings = bpy.context.scene.koma
        for name in settings.bl_rna.properties.keys():
            if name != "rna_type":
                settings.property_unset(name)
        settings.server = address
        obj30 = make_armature("take30", 150, 30)
        source30 = obj30.animation_data.action
        on_grid = expected_source_frames(obj30, address, timing_fps=24.0,
                                         output_rate="TIMING_RATE", return_motion=False)
        runs = []
        for t, frame in enumerate(on_grid.source_frames):
            if t == 0 or frame != on_grid.source_frames[t - 1]:
                runs.append(0)
            runs[-1] += 1
        seconds = len(on_grid.source_frames) / 24.0
        runs.sort()
        assert runs[(len(runs) - 1) // 2] >= 2, runs
        assert 7.5 <= len(runs) / seconds <= 12.5, (len(runs), seconds)
        assert on_grid.counts["omissions_applied"] >= 0.5 * seconds, on_grid.counts
        expected_default = expected_source_frames(obj30, address, return_motion=False)
        result = run_operator({})
        assert result == {"FINISHED"}, result
        check_anime_action(obj30, source30, expected_default)
        print(f"defaults: {len(runs)} drawings in {seconds:.2f} s, {expected_default.counts}")

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

        settings.server = address
        check_xsheet(address, workdir)
        check_file_mode(address, cli_bin, source_dir, workdir)
    finally:
        stop_server(process)
    print("koma Blender add-on test: PASS")


main()

"""Apply X-sheet (issue 46): the add-on's "Apply X-sheet" operator on an armature's action with
an XDTS sheet written here as a timing director would leave it (drawings swapped, a hold
lengthened, a drawing repeated later, a frame blank: SYMBOL_NULL_CELL), and with koma's
--timing CSV; the new action shows at every frame the source pose its cell names (a blank
holds the frame before), the same map the Python package gives for the same sheet. Then a
sheet that names a frame the action does not have: the operator cancels and writes nothing.
"""
import json
import os
import types

import bpy

from blender_test_helpers import check_anime_action, expected_source_frames, make_armature

IDENTIFIER = "exchangeDigitalTimeSheet Save Data"


def xdts(rows, name):
    """An XDTS with one Cell track: an entry where the cell changes, None as SYMBOL_NULL_CELL."""
    frames = []
    for r, s in enumerate(rows):
        if r == 0 or s != rows[r - 1]:
            value = "SYMBOL_NULL_CELL" if s is None else str(s + 1)
            frames.append({"data": [{"id": 0, "values": [value]}], "frame": r})
    frames.append({"data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}], "frame": len(rows)})
    document = {"timeTables": [{"duration": len(rows), "name": name,
                                "fields": [{"fieldId": 0, "tracks": [{"frames": frames,
                                                                      "trackNo": 0}]}],
                                "timeTableHeaders": [{"fieldId": 0, "names": [name]}]}],
                "version": 5}
    return IDENTIFIER + "\n" + json.dumps(document, indent=4, sort_keys=True) + "\n"


def shown(rows):
    """Per frame the source frame shown: a blank holds the frame before."""
    out = []
    for s in rows:
        out.append(out[-1] if s is None else s)
    return out


def apply(settings_values):
    settings = bpy.context.scene.koma
    for key, value in settings_values.items():
        setattr(settings, key, value)
    return bpy.ops.koma.apply_xsheet()


def check_xsheet(address, workdir):
    obj = make_armature("sheet24", 36, 24)  # 24 fps: the grid's rate, one row per frame
    source = obj.animation_data.action
    # On threes from the source's own frames, then the edits.
    rows = [3 * (r // 3) for r in range(36)]
    rows[3:6], rows[6:9] = [6] * 3, [3] * 3          # two drawings swapped
    rows[12:14] = [rows[11]] * 2                      # a hold lengthened by 2 frames
    rows[30:32] = [0, 0]                              # a drawing repeated later
    rows[20] = None                                   # a frame left blank
    sheet = os.path.join(workdir, "edited.xdts")
    with open(sheet, "w") as f:
        f.write(xdts(rows, "sheet24"))
    result = apply({"server": bpy.context.scene.koma.server, "xsheet_file": sheet})
    assert result == {"FINISHED"}, result
    want = shown(rows)
    check_anime_action(obj, source, types.SimpleNamespace(source_frames=want))
    obj.animation_data.action = source
    by_package = expected_source_frames(obj, address, timing_from=sheet, return_motion=False)
    assert by_package.source_frames == want, by_package.source_frames

    # The same timing as koma's --timing CSV (0-based source_frame, blank = empty).
    bpy.data.actions.remove(bpy.data.actions[source.name + ".anime"])
    csv = os.path.join(workdir, "edited.csv")
    with open(csv, "w") as f:
        f.write("output_frame,source_frame,kind,time_s\n")
        for r, s in enumerate(rows):
            f.write(f"{r},{'' if s is None else s},HELD,0\n")
    assert apply({"xsheet_file": csv}) == {"FINISHED"}
    check_anime_action(obj, source, types.SimpleNamespace(source_frames=want))

    # A cell past the action's 36 frames: cancelled, nothing written.
    obj.animation_data.action = source
    bpy.data.actions.remove(bpy.data.actions[source.name + ".anime"])
    bad = os.path.join(workdir, "bad.xdts")
    with open(bad, "w") as f:
        f.write(xdts(rows[:10] + [99] + rows[11:], "sheet24"))
    actions_before = len(bpy.data.actions)
    try:
        result = apply({"xsheet_file": bad})
        assert result == {"CANCELLED"}, result
    except RuntimeError as error:  # bpy.ops raises on an ERROR report
        assert 'frame 11: cell "100" names no drawing' in str(error), error
    assert len(bpy.data.actions) == actions_before
    assert obj.animation_data.action == source
    print(f"apply X-sheet: {len(want)} frames as edited, XDTS and CSV")

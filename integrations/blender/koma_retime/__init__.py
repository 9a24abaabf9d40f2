"""koma for Blender: retime the active armature's action into anime timing (RetimeSkeletal).

The operator samples the bones' world head positions over the action's frame range (the
positions form of RetimeSkeletal: no BVH export), asks a koma_server for the timing map, and
writes a new action "<name>.anime" on the armature: every output frame t is keyed with the pose
of source frame source_frames[t] (each F-curve of the action evaluated there), with CONSTANT
interpolation, so playback shows held drawings. The original action is kept (fake user).

Installed from its zip (build/dist/koma_retime-VERSION.zip: Preferences > Add-ons > Install),
it carries the pure-Python `koma` package; only grpcio and protobuf must come from Blender's
Python (Debian's Blender imports Debian's python3-grpcio). Run from the repository's folder
instead, it needs the `koma` package of a build (build/python, docs/python.md): set the
add-on's preference "koma package folder" (or the KOMA_PYTHONPATH environment variable) to the
folder that holds it. The preference and the variable win over the bundled copy.
"""
import os
import sys

import bpy

bl_info = {
    "name": "koma: anime timing",
    "author": "koma",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > koma",
    "description": "Inbetween omission and holds on the active armature's action (koma_server)",
    "category": "Animation",
}


# The koma package the installable zip carries (integrations/blender/make_addon_zip.py).
_BUNDLED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bundled")


def _import_koma(folder=""):
    """The koma package: from `folder` (the preference), else $KOMA_PYTHONPATH, else the copy
    bundled in the add-on's zip, else Python's own path. The first of these folders that holds
    a `koma` package goes first on sys.path."""
    for path in (folder, os.environ.get("KOMA_PYTHONPATH", ""), _BUNDLED):
        if path and os.path.isdir(os.path.join(path, "koma")):
            if path not in sys.path:
                sys.path.insert(0, path)
            break
    import koma
    return koma


class KomaPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__

    package_folder: bpy.props.StringProperty(
        name="koma package folder", subtype="DIR_PATH",
        description="Folder holding the koma Python package (a koma build's build/python); "
                    "empty: $KOMA_PYTHONPATH, else the copy in the add-on's zip, else "
                    "Python's own path")

    def draw(self, context):
        self.layout.prop(self, "package_folder")


class KomaSettings(bpy.types.PropertyGroup):
    """The panel's options, stored on the scene."""
    server: bpy.props.StringProperty(name="Server", default="127.0.0.1:50051",
                                     description="koma_server host:port")
    omissions: bpy.props.IntProperty(
        name="Omissions", default=-1, min=-1,
        description="Inbetween omission steps (the fastest frames go); -1: the server's "
                    "default (one a second of the action; with a count set, the paper's 4)")
    holds: bpy.props.IntProperty(
        name="Holds", default=-1, min=-1,
        description="Hold steps (the stillest frames repeat their predecessor); -1: the "
                    "server's default (as the drawing rate needs; with a count set, frames / 3)")
    max_hold: bpy.props.IntProperty(
        name="Max hold", default=0, min=0,
        description="Longest run of one drawing, in frames; 0: the server's default (3, or "
                    "the hold the drawing rate needs)")
    preset: bpy.props.EnumProperty(
        name="Preset", default="ANIME",
        items=[("ANIME", "Anime (default)",
                "The server's defaults: on threes (8 drawings a second) with one omission a "
                "second of the action"),
               ("PAPER", "Paper", "The paper's counts: 4 omissions, frames / 3 holds, on threes"),
               ("TWOS", "On twos", "12 drawings a second: a median hold of 2 grid frames"),
               ("THREES", "On threes", "8 drawings a second: a median hold of 3 grid frames")],
        description="Timing preset, as koma --preset (values set below win)")
    omissions_per_second: bpy.props.FloatProperty(
        name="Omissions / s", default=0.0, min=0.0,
        description="Omission rate per second of the action, so long takes snap as often as "
                    "short ones; 0: use Omissions (or the server's default)")
    drawings_per_second: bpy.props.FloatProperty(
        name="Drawings / s", default=0.0, min=0.0,
        description="Drawing rate (12 on twos, 8 on threes); 0: the preset's, or the "
                    "server's default")
    timing_fps: bpy.props.FloatProperty(
        name="Timing rate", default=24.0, min=0.0, max=1000.0,
        description="Film grid the drawings are counted on, frames per second (0: the "
                    "scene's own frames)")
    timeout: bpy.props.FloatProperty(name="Timeout", default=60.0, min=0.1,
                                     description="Seconds the server may take")


def sample_positions(context, armature, start, end):
    """(bone names, parent indices, frame-major world head positions) over frames start..end."""
    bones = list(armature.pose.bones)
    names = [b.name for b in bones]
    index = {name: i for i, name in enumerate(names)}
    parents = [index[b.parent.name] if b.parent else -1 for b in bones]
    scene = context.scene
    current = scene.frame_current
    values = []
    try:
        for frame in range(start, end + 1):
            scene.frame_set(frame)
            evaluated = armature.evaluated_get(context.evaluated_depsgraph_get())
            world = evaluated.matrix_world
            for name in names:
                head = world @ evaluated.pose.bones[name].head
                values.extend((head.x, head.y, head.z))
    finally:
        scene.frame_set(current)
    return names, parents, values


def write_anime_action(source, start, source_frames):
    """A new action "<source>.anime": output frame t (Blender frame start + t) of every F-curve
    keyed with the curve's value at frame start + source_frames[t], CONSTANT interpolation."""
    action = bpy.data.actions.new(source.name + ".anime")
    for curve in source.fcurves:
        group = curve.group.name if curve.group else ""
        out = action.fcurves.new(curve.data_path, index=curve.array_index, action_group=group)
        out.keyframe_points.add(len(source_frames))
        for t, frame in enumerate(source_frames):
            point = out.keyframe_points[t]
            point.co = (start + t, curve.evaluate(start + frame))
            point.interpolation = "CONSTANT"
        out.update()
    action["koma_source_frames"] = list(source_frames)
    action["koma_start_frame"] = start
    return action


# The panel's presets by the koma package's names (koma --preset; its table, koma._presets,
# says what each sets); ANIME is none: the server's defaults.
PRESET_NAMES = {"PAPER": "paper", "TWOS": "twos", "THREES": "threes"}


def request_options(settings):
    """The RetimeSkeletal options of the panel's settings (unset ones: the server's defaults),
    with `preset` for Client.retime_skeletal (values set here win over it)."""
    options = {"timing_fps": settings.timing_fps, "return_motion": False,
               "preset": PRESET_NAMES.get(settings.preset)}
    if settings.max_hold > 0:
        options["max_hold"] = settings.max_hold
    if settings.omissions_per_second > 0:
        options["omissions_per_second"] = settings.omissions_per_second
    elif settings.omissions >= 0:
        options["omissions"] = settings.omissions
    if settings.holds >= 0:
        options["holds"] = settings.holds
    if settings.drawings_per_second > 0:
        options["drawings_per_second"] = settings.drawings_per_second
    return options


class KOMA_OT_retime_action(bpy.types.Operator):
    """Retime the active armature's action into anime timing with a koma_server"""
    bl_idname = "koma.retime_action"
    bl_label = "Retime action (koma)"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return (obj is not None and obj.type == "ARMATURE" and obj.animation_data is not None
                and obj.animation_data.action is not None)

    def execute(self, context):
        settings = context.scene.koma
        armature = context.active_object
        source = armature.animation_data.action
        start, end = (int(round(f)) for f in source.frame_range)
        if end - start < 1:
            self.report({"ERROR"}, f"{source.name}: needs at least 2 frames")
            return {"CANCELLED"}
        try:
            addon = context.preferences.addons.get(__name__)
            koma = _import_koma(addon.preferences.package_folder if addon else "")
        except ImportError as error:
            self.report({"ERROR"}, f"cannot import koma ({error}); set the add-on's koma "
                                   "package folder")
            return {"CANCELLED"}
        names, parents, values = sample_positions(context, armature, start, end)
        fps = context.scene.render.fps / context.scene.render.fps_base
        options = request_options(settings)
        try:
            with koma.Client(settings.server, timeout=settings.timeout) as client:
                result = client.retime_skeletal(
                    koma.Positions(names, parents, 1.0 / fps, values), **options)
        except koma.KomaError as error:
            self.report({"ERROR"}, f"koma: {error.code.name}: {error.message}")
            return {"CANCELLED"}
        source.use_fake_user = True
        anime = write_anime_action(source, start, result.source_frames)
        armature.animation_data.action = anime
        c = result.counts
        cuts = f"; cuts before frames {result.cut_frames}" if result.cut_frames else ""
        self.report({"INFO"}, f"{anime.name}: {c['frames']} frames, omitted "
                              f"{c['omissions_applied']}, held {c['holds_applied']}{cuts}")
        return {"FINISHED"}


class KOMA_PT_panel(bpy.types.Panel):
    bl_label = "koma: anime timing"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "koma"

    def draw(self, context):
        settings = context.scene.koma
        layout = self.layout
        for name in ("preset", "omissions", "omissions_per_second", "holds", "max_hold",
                     "drawings_per_second", "timing_fps", "server", "timeout"):
            layout.prop(settings, name)
        layout.operator(KOMA_OT_retime_action.bl_idname)


_classes = (KomaPreferences, KomaSettings, KOMA_OT_retime_action, KOMA_PT_panel)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.koma = bpy.props.PointerProperty(type=KomaSettings)


def unregister():
    del bpy.types.Scene.koma
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)

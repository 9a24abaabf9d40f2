"""koma for Blender: retime the active armature's action, or a motion file, into anime timing
(RetimeSkeletal).

Action mode: the operator samples the bones' world head positions over the action's frame range (the
positions form of RetimeSkeletal: no BVH export), asks a koma_server for the timing map, and
writes a new action "<name>.anime" on the armature: every output frame t is keyed with the pose
of source frame source_frames[t] (each F-curve of the action evaluated there), with CONSTANT
interpolation, so playback shows held drawings. The original action is kept (fake user).

File mode: the operator sends a motion file (FBX, glTF/GLB/VRM, BVH) as it is to the server (a
file request, as `koma skeletal FILE -o OUT`), writes the retimed file the server returns
(default next to the source, "<name>.anime.<ext>"), byte for byte what the CLI and the Python
package write for the same options, and imports it with Blender's own importer for its format.

Installed from its zip (build/dist/koma_retime-VERSION.zip: Preferences > Add-ons > Install),
it carries the pure-Python `koma` package; only grpcio and protobuf must come from Blender's
Python (Debian's Blender imports Debian's python3-grpcio). Run from the repository's folder
instead, it needs the `koma` package of a build (build/python, docs/python.md): set the
add-on's preference "koma package folder" (or the KOMA_PYTHONPATH environment variable) to the
folder that holds it. The preference and the variable win over the bundled copy.
"""
import builtins
import os
import pathlib
import sys

import bpy

bl_info = {
    "name": "koma: anime timing",
    "author": "koma",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > koma",
    "description": "Inbetween omission and holds on the active armature's action or a motion "
                   "file (FBX, glTF, BVH) (koma_server)",
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
    motion_file: bpy.props.StringProperty(
        name="Motion file", subtype="FILE_PATH",
        description="File mode: the motion file to retime (.fbx, .glb, .gltf, .vrm, .vrma, "
                    ".bvh), sent to the server as it is")
    output_file: bpy.props.StringProperty(
        name="Output", subtype="FILE_PATH",
        description="File mode: where the retimed file goes; empty: next to the motion file, "
                    "as <name>.anime.<ext>")
    take: bpy.props.StringProperty(
        name="Take", description="File mode: the FBX take or the glTF animation to retime; "
                                 "empty: the server's default (an FBX file's current take, "
                                 "every glTF animation)")
    xsheet_file: bpy.props.StringProperty(
        name="X-sheet", subtype="FILE_PATH",
        description="Apply X-sheet: an exposure sheet an animator edited (.xdts from koma "
                    "--xdts, CLIP STUDIO PAINT, OpenToonz, TVPaint) or a koma --timing CSV; "
                    "cell N shows source frame N, a blank cell holds the frame before")
    last_summary: bpy.props.StringProperty(
        name="Last result", description="What the last file retime did (also in the Info log)")


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
    """The RetimeSkeletal options of the panel's settings (unset ones, and the timing rate left
    at its default: not sent, so the server's defaults apply), with `preset` for
    Client.retime_skeletal (values set here win over it)."""
    options = {"preset": PRESET_NAMES.get(settings.preset)}
    if settings.is_property_set("timing_fps"):
        options["timing_fps"] = settings.timing_fps
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


def _koma_or_none(operator, context):
    """The koma package as the add-on's preference finds it, or None with an error report."""
    try:
        addon = context.preferences.addons.get(__name__)
        return _import_koma(addon.preferences.package_folder if addon else "")
    except ImportError as error:
        operator.report({"ERROR"}, f"cannot import koma ({error}); set the add-on's koma "
                                   "package folder")
        return None


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
        return retime_active_action(self, context, None)


def retime_active_action(operator, context, xsheet):
    """The active armature's action retimed (xsheet None) or given the timing of the X-sheet
    at `xsheet`, into a new action "<name>.anime"."""
    settings = context.scene.koma
    armature = context.active_object
    source = armature.animation_data.action
    start, end = (int(round(f)) for f in source.frame_range)
    if end - start < 1:
        operator.report({"ERROR"}, f"{source.name}: needs at least 2 frames")
        return {"CANCELLED"}
    koma = _koma_or_none(operator, context)
    if koma is None:
        return {"CANCELLED"}
    names, parents, values = sample_positions(context, armature, start, end)
    fps = context.scene.render.fps / context.scene.render.fps_base
    options = dict(request_options(settings), return_motion=False)
    if xsheet is not None:
        options = {"timing_from": xsheet, "return_motion": False}
        if settings.is_property_set("timing_fps"):
            options["timing_fps"] = settings.timing_fps
    try:
        with koma.Client(settings.server, timeout=settings.timeout) as client:
            result = client.retime_skeletal(
                koma.Positions(names, parents, 1.0 / fps, values), **options)
    except koma.KomaError as error:
        operator.report({"ERROR"}, f"koma: {error.code.name}: {error.message}")
        return {"CANCELLED"}
    except koma.SheetError as error:
        operator.report({"ERROR"}, f"koma: {error}")
        return {"CANCELLED"}
    except OSError as error:
        operator.report({"ERROR"}, f"koma: cannot read {xsheet}: {error.strerror or error}")
        return {"CANCELLED"}
    for warning in result.warnings:
        operator.report({"WARNING"}, f"koma: {warning}")
    return write_result(operator, armature, source, start, result, xsheet)


def write_result(operator, armature, source, start, result, xsheet):
    """The "<name>.anime" action of `result`, made the armature's, and the report."""
    source.use_fake_user = True
    anime = write_anime_action(source, start, result.source_frames)
    armature.animation_data.action = anime
    c = result.counts
    if xsheet is not None:
        operator.report({"INFO"}, f"{anime.name}: {c['frames']} frames, the timing of "
                                  f"{os.path.basename(xsheet)}")
        return {"FINISHED"}
    cuts = f"; cuts before frames {result.cut_frames}" if result.cut_frames else ""
    operator.report({"INFO"}, f"{anime.name}: {c['frames']} frames, omitted "
                              f"{c['omissions_applied']}, held {c['holds_applied']}{cuts}")
    return {"FINISHED"}


class KOMA_OT_apply_xsheet(bpy.types.Operator):
    """Give the active armature's action the timing of an edited X-sheet (XDTS or koma's
    timing CSV): a new action "<name>.anime" showing, at every frame, the drawing its cell
    names"""
    bl_idname = "koma.apply_xsheet"
    bl_label = "Apply X-sheet (koma)"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return KOMA_OT_retime_action.poll(context)

    def execute(self, context):
        settings = context.scene.koma
        if not settings.xsheet_file:
            self.report({"ERROR"}, "koma: choose the X-sheet (.xdts or timing .csv) to apply")
            return {"CANCELLED"}
        return retime_active_action(self, context, bpy.path.abspath(settings.xsheet_file))


# File mode: the formats `koma skeletal` reads as its IN that Blender can import back (the
# retimed file comes in the same format), by their keys in the koma package's format table
# (formats/format_table.h), which says the rest: names, extensions, what takes them.
IMPORTED_FORMATS = ("fbx", "gltf", "bvh")


def file_extensions(koma):
    """The file names the file mode takes, from the format table: ".fbx", ".glb", ..."""
    table = koma._format_table
    return [extension for key in IMPORTED_FORMATS for extension in table.row(key)["extensions"]]


def file_format_of(koma, source):
    """The format name of `source` ("FBX", "glTF", "BVH") by its file name, as `koma skeletal`
    finds it; None when it is not one the file mode takes."""
    table = koma._format_table
    key = table.format_from_name(source)
    if key not in IMPORTED_FORMATS or ("skeletal", "") not in table.row(key)["inputs"]:
        return None
    return table.row(key)["name"]


def output_path(source, chosen=""):
    """Where the retimed file goes: `chosen` (a Blender path, "//" relative to the .blend), else
    next to `source` as "<name>.anime<ext>"."""
    if chosen:
        return bpy.path.abspath(chosen)
    stem, ext = os.path.splitext(source)
    return stem + ".anime" + ext


def file_request_options(settings, file_format):
    """request_options plus the take for the file's format (FBX fbx_take, glTF
    gltf_animations); empty take: not sent (the server's default)."""
    options = request_options(settings)
    take = settings.take.strip()
    if take:
        if file_format == "FBX":
            options["fbx_take"] = take
        elif file_format == "glTF":
            options["gltf_animations"] = [take]
        else:
            raise ValueError(f"Take {take!r}: a BVH file has one take; leave Take empty")
    return options


def _bvh_open(file, mode="r", *args, **kwargs):
    """open() without the 'U' mode Debian's Blender 3.4 BVH importer passes ('rU'), which
    Python 3.11 refuses."""
    return builtins.open(file, mode.replace("U", ""), *args, **kwargs)


def import_retimed(path, file_format, output_fps):
    """Imports `path` with Blender's importer for its format; the importer's result set.
    FBX: the importer sets the scene's rate to the file's. glTF: the importer keys at the
    scene's rate, so the scene gets the file's (output_fps) first. BVH: the importer sets the
    scene's rate and length (update_scene_fps, update_scene_duration). Two fixes for Debian's
    Blender 3.4 on Python 3.11 and numpy 1.24 are applied around the call only (_bvh_open, and
    numpy.bool below)."""
    scene = bpy.context.scene
    if file_format == "FBX":
        return bpy.ops.import_scene.fbx(filepath=path)
    if file_format == "glTF":
        if output_fps > 0:
            scene.render.fps = max(1, round(output_fps))
            scene.render.fps_base = scene.render.fps / output_fps
        # Debian's Blender 3.4 glTF importer uses numpy's `np.bool`, which Debian 12's numpy
        # 1.24 removed (it was an alias of the builtin): lent for the import only.
        import numpy
        lent = "bool" not in vars(numpy)  # (hasattr would warn)
        if lent:
            numpy.bool = bool
        try:
            return bpy.ops.import_scene.gltf(filepath=path)
        finally:
            if lent:
                del numpy.bool
    from io_anim_bvh import import_bvh
    patched = sys.version_info >= (3, 11) and "open" not in vars(import_bvh)
    if patched:
        import_bvh.open = _bvh_open
    try:
        return bpy.ops.import_anim.bvh(filepath=path, update_scene_fps=True,
                                       update_scene_duration=True)
    finally:
        if patched:
            del import_bvh.open


def short_error(error):
    """An operator's RuntimeError as one line: for a Python error inside the importer (the
    message is "Error: Python: Traceback ..."), its last line, the exception itself."""
    lines = [line.strip() for line in str(error).splitlines()
             if line.strip() and not line.strip().startswith("Location:")]
    if not lines:
        return type(error).__name__
    return lines[-1] if "Traceback" in lines[0] else lines[0].removeprefix("Error: ")


def drawings_shown(source_frames):
    """Runs of one drawing (source frame) in the output, as the CLI's summary counts them."""
    return sum(1 for t, f in enumerate(source_frames) if t == 0 or f != source_frames[t - 1])


def file_summary(result, out_path, file_format):
    """One line: what the retime did to the file (counts as the CLI's summary names them)."""
    c = result.counts
    parts = [f"{os.path.basename(out_path)}: {c['frames']} frames, "
             f"{drawings_shown(result.source_frames)} drawings, omitted "
             f"{c['omissions_applied']}, held {c['holds_applied']}"]
    if result.take is not None:
        parts.append(f"take \"{result.take['name']}\" at {result.take['output_fps']:g} fps")
    if result.animations:
        names = ", ".join(f"\"{a['name'] or a['index']}\"" for a in result.animations)
        parts.append(f"animations {names} at {result.animations[0]['output_fps']:g} fps")
    if result.cut_frames:
        parts.append(f"cuts before frames {result.cut_frames}")
    if result.warnings:
        parts.append(f"{len(result.warnings)} warning(s)")
    return "; ".join(parts)


class KOMA_OT_retime_file(bpy.types.Operator):
    """Retime a motion file (FBX, glTF, BVH) with a koma_server, write the retimed file and
    import it"""
    bl_idname = "koma.retime_file"
    bl_label = "Retime file (koma)"
    bl_options = {"REGISTER", "UNDO"}

    filepath: bpy.props.StringProperty(
        name="Motion file", subtype="FILE_PATH", options={"SKIP_SAVE"},
        description="The motion file; empty: the panel's Motion file")
    filter_glob: bpy.props.StringProperty(
        default="*.fbx;*.glb;*.gltf;*.vrm;*.vrma;*.bvh", options={"HIDDEN", "SKIP_SAVE"})

    def invoke(self, context, event):
        if self.filepath or context.scene.koma.motion_file:
            return self.execute(context)
        koma = _koma_or_none(self, context)
        if koma is not None:  # else the default above
            self.filter_glob = ";".join("*" + e for e in file_extensions(koma))
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def fail(self, message):
        bpy.context.scene.koma.last_summary = message
        self.report({"ERROR"}, message)
        return {"CANCELLED"}

    def execute(self, context):
        settings = context.scene.koma
        if self.filepath:
            settings.motion_file = self.filepath
        koma = _koma_or_none(self, context)
        if koma is None:
            return {"CANCELLED"}
        extensions = ", ".join(file_extensions(koma))
        if not settings.motion_file:
            return self.fail(f"koma: choose a motion file ({extensions})")
        source = bpy.path.abspath(settings.motion_file)
        file_format = file_format_of(koma, source)
        if file_format is None:
            return self.fail(f"koma: {os.path.basename(source)}: not a motion file koma "
                             f"takes ({extensions})")
        out_path = output_path(source, settings.output_file)
        if os.path.abspath(out_path) == os.path.abspath(source):
            return self.fail(f"koma: the output {out_path} is the motion file itself")
        try:
            options = file_request_options(settings, file_format)
            # By its path, as `koma skeletal FILE` sends it: the package reads the file and
            # puts it in the request's fbx, gltf or bvh_text field by its extension.
            with koma.Client(settings.server, timeout=settings.timeout) as client:
                result = client.retime_skeletal(pathlib.Path(source), **options)
        except koma.KomaError as error:
            return self.fail(f"koma: {error.code.name}: {error.message}")
        except OSError as error:
            return self.fail(f"koma: cannot read {source}: {error.strerror or error}")
        except (TypeError, ValueError) as error:
            return self.fail(f"koma: {error}")
        try:
            result.write(out_path)
        except (OSError, ValueError) as error:
            return self.fail(f"koma: cannot write {out_path}: "
                             f"{getattr(error, 'strerror', None) or error}")
        output_fps = result.animations[0]["output_fps"] if result.animations else 0.0
        objects_before = set(bpy.data.objects)
        try:
            if bpy.ops.object.mode_set.poll():
                bpy.ops.object.mode_set(mode="OBJECT")
            imported = import_retimed(out_path, file_format, output_fps)
        except RuntimeError as error:
            return self.fail(f"koma: wrote {out_path}, but Blender's {file_format} importer "
                             f"refused it: {short_error(error)}")
        if imported != {"FINISHED"}:
            return self.fail(f"koma: wrote {out_path}, but Blender's {file_format} importer "
                             f"returned {sorted(imported)}")
        new = [o for o in bpy.data.objects if o not in objects_before]
        armatures = [o for o in new if o.type == "ARMATURE"]
        summary = file_summary(result, out_path, file_format)
        for obj in armatures:
            data = obj.animation_data
            if data is not None and data.action is not None:
                data.action["koma_source_file"] = source
                data.action["koma_source_frames"] = list(result.source_frames)
        if armatures:
            context.view_layer.objects.active = armatures[0]
            summary += f"; imported as {armatures[0].name}"
            action = armatures[0].animation_data and armatures[0].animation_data.action
            if action is not None:
                scene = context.scene
                scene.frame_start, scene.frame_end = (int(round(f)) for f in action.frame_range)
                if file_format == "glTF":  # STEP keys: the last drawing lasts to the end
                    scene.frame_end = scene.frame_start + len(result.source_frames) - 1
        settings.last_summary = summary
        for warning in result.warnings:
            self.report({"WARNING"}, f"koma: {warning}")
        self.report({"INFO"}, summary)
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
        layout.prop(settings, "xsheet_file")
        layout.operator(KOMA_OT_apply_xsheet.bl_idname)
        box = layout.box()
        box.label(text="File (FBX, glTF, BVH)")
        for name in ("motion_file", "take", "output_file"):
            box.prop(settings, name)
        box.operator(KOMA_OT_retime_file.bl_idname)
        if settings.last_summary:
            box.label(text=settings.last_summary)


_classes = (KomaPreferences, KomaSettings, KOMA_OT_retime_action, KOMA_OT_apply_xsheet,
            KOMA_OT_retime_file, KOMA_PT_panel)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.koma = bpy.props.PointerProperty(type=KomaSettings)


def unregister():
    del bpy.types.Scene.koma
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)

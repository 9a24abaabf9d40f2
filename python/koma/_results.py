"""What the three calls return: the retimed file's text, the timing map and the counts."""
import os

from koma import _xdts
from koma.v1 import retime_pb2


def _kind_name(kind):
    return retime_pb2.FrameKind.Name(kind)


class _Result:
    """Common part: `output` (str, the retimed file) and writing it."""

    output_bytes = None
    source_path = None  # the input file's path when the call was given one

    def xdts(self, name=None):
        """The timing as an XDTS exposure sheet (str), byte for byte what `koma ... --xdts`
        writes (docs/formats.md). `name` names the sheet and its layers; default the input
        file's name without its extension (else "koma")."""
        return _xdts.write(self._xdts_sheet(name or _xdts.clip_name(self.source_path, None)))

    def write_xdts(self, path, name=None):
        """Writes xdts() to `path`; the default name is the input file's, else `path`'s, without
        the extension."""
        text = self.xdts(name or _xdts.clip_name(self.source_path, os.fspath(path)))
        with open(path, "wb") as out:
            out.write(text.encode("utf-8"))

    @property
    def output(self):
        """The retimed file's text (str), or None when the request sent no file or asked
        for no motion (return_motion=False), or the file is binary (a GLB: output_bytes)."""
        if self.output_bytes is None or self.output_bytes.startswith(b"glTF"):
            return None
        return self.output_bytes.decode("utf-8")

    def write(self, path):
        """Writes the retimed file to `path`, byte for byte as the server wrote it (what
        `koma ... -o path` writes). ValueError when there is no file to write."""
        if self.output_bytes is None:
            raise ValueError("no retimed file in this result (the request carried no file, "
                             "or return_motion was False)")
        with open(path, "wb") as out:
            out.write(self.output_bytes)


class SkeletalResult(_Result):
    """A RetimeSkeletal answer.

    Attributes:
        output / output_bytes: the retimed BVH (file requests), as `koma skeletal -o` writes it;
            for a glTF or FBX request output_bytes is the retimed file (output only for a
            .gltf, which is text).
        take: for an FBX request, the take as read: a dict of name, source_fps, start_s,
            frame_count, joints, output_fps, layers and curves_written; else None.
        animations: for a glTF request, per retimed animation a dict: index, name,
            source_fps, start_s, frame_count, joints, output_fps, keys_written, and its
            source_frames (the fields above are the first one's).
        source_frames: per output frame t, the 0-based source frame it shows.
        kinds: per output frame, "ORIGINAL", "DUPLICATE" or "HELD".
        timing: the timing map as a dict {output frame: source frame}.
        counts: dict with frames (output frames), omissions_applied, duplicates_applied,
            duplicates_skipped, duplicates_omitted and duplicates_held (duplicates a later
            omission removed or a later hold held over), holds_applied, omissions_requested,
            holds_requested, max_hold (counts in grid frames when timing_fps > 0).
        deleted_frames, hidden_frames: source frames no longer shown (omitted / held over).
        input_ssd: per input frame (grid frame with a grid) the squared distance to the one
            before, in squared length units.
        timing_fps: the film grid used in frames per second; 0 when counting source frames.
        grid_frames, grid_source_frames: with a grid, per output frame its grid frame, and
            per grid frame its sampled source frame.
        cut_frames: per cut (an isolated jump such as a T-pose first frame), the source frame
            starting the shot after it; [] for a clip of one shot.
        frame_time: seconds per output frame (with a decoded motion or a file), else None.
        omissions_per_second, drawings_per_second: the rates the server used (the options',
            or with no count given the anime defaults 1 and 8); 0 where none applied.
        warnings: where the file bent a rule and was read anyway, one sentence each
            ("bvh_text: line 3075: ..."); [] for a file that keeps every rule.
        response: the koma.v1.RetimeSkeletalResponse message itself.
    """

    def __init__(self, response):
        self.response = response
        self.output_bytes = response.bvh_text if response.bvh_text else None
        if response.gltf:
            self.output_bytes = response.gltf
        if response.fbx:
            self.output_bytes = response.fbx
        self.take = None
        if response.HasField("fbx_take"):
            t = response.fbx_take
            self.take = {
                "name": t.name, "source_fps": t.source_fps, "start_s": t.start_s,
                "frame_count": t.frame_count, "joints": list(t.joints), "output_fps": t.output_fps,
                "layers": t.layers, "curves_written": t.curves_written,
            }
        self.animations = [{
            "index": a.index, "name": a.name, "source_fps": a.source_fps, "start_s": a.start_s,
            "frame_count": a.frame_count, "joints": list(a.joints), "output_fps": a.output_fps,
            "keys_written": a.keys_written, "source_frames": list(a.timing.source_frames),
        } for a in response.gltf_animations]
        self.source_frames = list(response.source_frames)
        self.kinds = [_kind_name(k) for k in response.kinds]
        self.timing = dict(enumerate(self.source_frames))
        self.deleted_frames = list(response.deleted_frames)
        self.hidden_frames = list(response.hidden_frames)
        self.input_ssd = list(response.input_ssd)
        self.timing_fps = response.timing_fps
        self.grid_frames = list(response.grid_frames)
        self.grid_source_frames = list(response.grid_source_frames)
        self.cut_frames = list(response.cut_frames)
        self.frame_time = response.motion.frame_time if response.HasField("motion") else None
        self.omissions_per_second = response.omissions_per_second
        self.drawings_per_second = response.drawings_per_second
        self.warnings = list(response.warnings)
        self.counts = {
            "frames": len(self.source_frames),
            "omissions_applied": response.omissions_applied,
            "duplicates_applied": response.duplicates_applied,
            "duplicates_skipped": response.duplicates_skipped,
            "duplicates_omitted": response.duplicates_omitted,
            "duplicates_held": response.duplicates_held,
            "holds_applied": response.holds_applied,
            "omissions_requested": response.omissions_requested,
            "holds_requested": response.holds_requested,
            "max_hold": response.max_hold,
        }

    def _xdts_sheet(self, name):
        return _xdts.skeletal_sheet(self.response, name)

    def __repr__(self):
        return f"SkeletalResult(counts={self.counts})"


# KeyDrawing.role as the word docs/python.md uses.
_KEY_ROLES = {retime_pb2.KEY_ROLE_FIRST: "first", retime_pb2.KEY_ROLE_LAST: "last",
              retime_pb2.KEY_ROLE_EXTREME: "extreme"}


class CurvesResult(_Result):
    """A RetimeCurves answer.

    Attributes:
        output / output_bytes: the retimed motion3.json, Spine skeleton or CSV (file
            requests), as `koma curves IN -o OUT` writes it.
        key_frames: the key poses used (frames, ascending): the default group's.
        key_frames_merged: per key pose, how many keyframe times it merges (empty when the
            key poses were named or merging was off).
        groups: {group name: {"curves": [curve ids], "frames_per_drawing": n,
            "key_frames": [...], "key_frames_merged": [...], "timing": index into timings}},
            the default group "body" first; empty when every curve is in the default group.
        timing: the default timing map {output frame: source time in frames (fractional)};
            timings has every timing (one more per distinct curve override).
        timings: list of dicts: frames_per_drawing, drawing_of_frame, source_frame,
            drawing_start, drawing_start_grid (frames; grid frames for the last).
        curves: {curve id: {"timing": index into timings (-1: a GROUP_KEEP curve, as it came
            in), "values": per-frame values, "holds": {length in frames: drawings} (empty for
            kept curves and the mouth and eyes LipBlink draws), "keys": the keys koma draws
            exactly (docs/semantics.md, "Every key is drawn"): [{"frame", "value", "role"
            ("first", "last" or "extreme"), "drawing", "drawn", "displaced"}]}}.
        counts: dict with curves, frames, key_poses, drawings (of the default timing).
        timing_fps: the film grid used (frames per second); 0 when counting source frames.
        response: the koma.v1.RetimeCurvesResponse message itself.
    """

    def __init__(self, response):
        self.response = response
        which = response.WhichOneof("output")
        self.output_bytes = getattr(response, which) if which else None
        self.key_frames = list(response.key_frames)
        self.key_frames_merged = list(response.key_frames_merged)
        self.groups = {g.name: {"curves": [response.curves[c].id for c in g.curves],
                                "frames_per_drawing": g.frames_per_drawing,
                                "key_frames": list(g.key_frames),
                                "key_frames_merged": list(g.key_frames_merged),
                                "timing": g.timing}
                       for g in response.timing_groups}
        self.timing_fps = response.timing_fps
        self.timings = [{
            "frames_per_drawing": t.frames_per_drawing,
            "drawing_of_frame": list(t.drawing_of_frame),
            "source_frame": list(t.source_frame),
            "drawing_start": list(t.drawing_start),
            "drawing_start_grid": list(t.drawing_start_grid),
        } for t in response.timings]
        self.timing = dict(enumerate(self.timings[0]["source_frame"])) if self.timings else {}
        self.curves = {c.id: {"timing": c.timing, "values": list(c.values),
                              "holds": {h.length: h.drawings for h in c.hold_histogram},
                              "keys": [{"frame": k.frame, "value": k.value,
                                        "role": _KEY_ROLES.get(k.role, "unspecified"),
                                        "drawing": k.drawing, "drawn": k.drawn,
                                        "displaced": k.displaced} for k in c.keys]}
                       for c in response.curves}
        self.counts = {
            "curves": len(response.curves),
            "frames": len(self.timing),
            "key_poses": len(self.key_frames),
            "drawings": len(self.timings[0]["drawing_start"]) if self.timings else 0,
        }

    def _xdts_sheet(self, name):
        return _xdts.curves_sheet(self.response, name)

    def __repr__(self):
        return f"CurvesResult(counts={self.counts})"


class LipBlinkResult(_Result):
    """A LipBlink answer.

    Attributes:
        output / output_bytes: the converted motion3.json or CSV (file requests), or the
            Spine skeleton with its slots keyed, as `koma lipblink IN -o OUT` writes it.
        mouths: list of {"id", "speech": [(begin, end)], "holds": [(begin, length, shape)],
            "closed_level", "mid_level", "open_level"}; frames (grid frames with a grid).
        eyes: list of {"id", "blinks": [dict of closing_begin, closed_begin, closed_end,
            open_span, hold, automatic], "closed_level", "mid_level", "open_level"}.
        timing: {curve id: its mouth holds or its blinks, as in mouths / eyes}.
        curves: {curve id: per-frame values} of the converted curves.
        counts: dict with mouth_curves, eye_curves, mouth_holds, blinks.
        seed: the seed used. timing_fps: the film grid used; 0 when counting source frames.
        voice: with audio or rhubarb_cues, a dict of the analysis: sample_rate, channels,
            duration_s, frame_fps, loudness_dbfs (per frame), noise_floor_dbfs, start_dbfs,
            stay_dbfs, loud_dbfs, speech [(begin, end)] (frames of frame_fps); else None.
        rhubarb_json, rhubarb_tsv: with a voice, the mouth as Rhubarb cues (str); else None.
        response: the koma.v1.LipBlinkResponse message itself.
    """

    def __init__(self, response):
        self.response = response
        which = response.WhichOneof("output")
        self.output_bytes = getattr(response, which) if which else None
        self.seed = response.seed
        self.timing_fps = response.timing_fps
        self.mouths = [{
            "id": m.id,
            "speech": [(i.begin, i.end) for i in m.speech],
            "holds": [(h.begin, h.length, retime_pb2.MouthShape.Name(h.shape)) for h in m.holds],
            "closed_level": m.closed_level, "mid_level": m.mid_level, "open_level": m.open_level,
        } for m in response.mouths]
        self.eyes = [{
            "id": e.id,
            "blinks": [{"closing_begin": b.closing_begin, "closed_begin": b.closed_begin,
                        "closed_end": b.closed_end, "open_span": b.open_span, "hold": b.hold,
                        "automatic": b.automatic} for b in e.blinks],
            "closed_level": e.closed_level, "mid_level": e.mid_level, "open_level": e.open_level,
        } for e in response.eyes]
        self.timing = {m["id"]: m["holds"] for m in self.mouths}
        self.timing.update({e["id"]: e["blinks"] for e in self.eyes})
        self.curves = {c.id: list(c.values) for c in response.curves}
        self.voice = None
        self.rhubarb_json = self.rhubarb_tsv = None
        if response.HasField("voice"):
            v = response.voice
            self.voice = {
                "sample_rate": v.sample_rate, "channels": v.channels,
                "duration_s": v.duration_s, "frame_fps": v.frame_fps,
                "loudness_dbfs": list(v.loudness_dbfs), "noise_floor_dbfs": v.noise_floor_dbfs,
                "start_dbfs": v.start_dbfs, "stay_dbfs": v.stay_dbfs, "loud_dbfs": v.loud_dbfs,
                "speech": [(i.begin, i.end) for i in v.speech],
            }
            self.rhubarb_json = response.rhubarb_json.decode("utf-8")
            self.rhubarb_tsv = response.rhubarb_tsv.decode("utf-8")
        self.counts = {
            "mouth_curves": len(self.mouths),
            "eye_curves": len(self.eyes),
            "mouth_holds": sum(len(m["holds"]) for m in self.mouths),
            "blinks": sum(len(e["blinks"]) for e in self.eyes),
        }

    def _xdts_sheet(self, name):
        # The grid's rows need the curves' own rate: the file's Meta.Fps, or the CSV's csv_fps.
        return _xdts.lip_blink_sheet(self.response, self._source_fps(), name)

    def __repr__(self):
        return f"LipBlinkResult(counts={self.counts})"

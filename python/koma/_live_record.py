"""A live stream's frames as a Live2D motion3.json: ParamMouthOpenY (the mouth level) and
ParamEyeLOpen / ParamEyeROpen (the eye level), stepped (segment type 2) on the film grid.

Meta.Fps is the grid's rate (24), so each drawing starts on a whole frame; the last point is
at the end of the last frame, Meta.Duration = frames / fps. The Meta counts are Live2D's (one
point per curve's start plus one per stepped segment), as koma's own writer counts them
(formats/motion3_writer.cc), and `koma curves` / `koma lipblink` read the file back.
"""
import json

MOUTH_ID = "ParamMouthOpenY"
EYE_IDS = ("ParamEyeLOpen", "ParamEyeROpen")
STEPPED = 2


def _number(value):
    """An integer-valued float as an int (0 rather than 0.0), as koma writes numbers."""
    value = float(value)
    return int(value) if value.is_integer() and abs(value) < 2 ** 53 else value


def _segments(values, fps):
    """[t0, v0, 2, t1, v1, ...]: a stepped key where the value changes, and the end."""
    segments = [0, _number(values[0])]
    for g in range(1, len(values)):
        if values[g] != values[g - 1]:
            segments += [STEPPED, _number(g / fps), _number(values[g])]
    segments += [STEPPED, _number(len(values) / fps), _number(values[-1])]
    return segments


class Motion3Recorder:
    """Collects frames (LiveFrame) and writes them as a motion3.json."""

    def __init__(self, fps=24.0, mouth_id=MOUTH_ID, eye_ids=EYE_IDS):
        self.fps = float(fps)
        self.mouth_id = mouth_id
        self.eye_ids = tuple(eye_ids)
        self.mouth = []
        self.eyes = []

    def add(self, frame):
        self.mouth.append(frame.mouth_level)
        self.eyes.append(frame.eye_level)

    def document(self):
        curves = []
        if self.mouth:
            curves.append((self.mouth_id, _segments(self.mouth, self.fps)))
            for eye in self.eye_ids:
                curves.append((eye, _segments(self.eyes, self.fps)))
        segment_count = sum((len(s) - 2) // 3 for _, s in curves)
        return {
            "Version": 3,
            "Meta": {
                "Duration": _number(len(self.mouth) / self.fps),
                "Fps": _number(self.fps),
                "Loop": False,
                "AreBeziersRestricted": True,
                "CurveCount": len(curves),
                "TotalSegmentCount": segment_count,
                "TotalPointCount": len(curves) + segment_count,
                "UserDataCount": 0,
                "TotalUserDataSize": 0,
            },
            "Curves": [{"Target": "Parameter", "Id": curve_id, "Segments": segments}
                       for curve_id, segments in curves],
        }

    def write(self, path):
        with open(path, "w", encoding="utf-8") as f:
            json.dump(self.document(), f, indent="\t", ensure_ascii=False)
            f.write("\n")

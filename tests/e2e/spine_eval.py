"""An independent Spine JSON evaluator and film-grid checker for koma's Spine tests.

Written from Spine's published JSON format documentation (esotericsoftware.com/spine-json-format),
not from koma's C++ reader nor from Spine's runtimes: bone rotate/translate/scale/shear
timelines (3.x `angle`, x/y; 4.x `value`, x/y and the separate translatex/... timelines), their
curves (absent or "linear": linear; "stepped"; a Bezier: 3.7 `curve: [cx1, cy1, cx2, cy2]`, 3.8
`curve: cx1, c2, c3, c4` normalised to the segment, 4.x `curve: [cx1, cy1, cx2, cy2, ...]`
absolute per value), the setup pose before a timeline's first key, the last value after it;
key times within Spine's 4-decimal rounding of a frame taken as that frame, as koma documents
(docs/formats.md). A Bezier with a handle outside its segment is played as the Spine runtimes
are observed to play it (docs/formats.md): sampled at u = 0, 0.1, ..., 1, and for a time the
first sample at or after it interpolated from the sample before; the key's own time shows the
key.

check(before, after, animations): for every bone value of every animation retimed, at every
grid time g / 24 s, the output's value equals what the drawing shown on grid frame g must show
of that value (docs/semantics.md): key poses snapped to the grid and merged, max(1, L // 3)
drawings per segment held as evenly as possible, longer holds first, drawing j at
T_x + (T_{x+1} - T_x) * j / D between the key poses' own times; and every key drawn: the
value's first, last and extreme keys shown exactly by the drawing whose hold contains them (a
key that loses its drawing to a larger swing moves next door when no key falls there), the
other drawings at their tau clamped between the keys drawn around them.
"""
import json
import math
import sys

GRID_FPS = 24
ON = 3


def _round_half_away(x):
    return int(math.floor(abs(x) + 0.5)) * (1 if x >= 0 else -1)


def key_time(t, fps):
    """A key's time as read (docs/formats.md, "Key times to 4 decimals"): Spine writes 4
    decimals, so a time within 0.00005 s (+ 1e-6 frame) of a whole frame is that frame's."""
    frame = round(t * fps)
    return frame / fps if abs(t * fps - frame) <= 0.00005 * fps + 1e-6 else t


class Timeline:
    def __init__(self, keys, fields, component, neutral, major, fps):
        self.times = [key_time(float(k.get("time", 0)), fps) for k in keys]
        self.values = [float(k.get(fields[component], neutral)) for k in keys]
        self.neutral = neutral
        self.beziers = []
        for i, key in enumerate(keys):
            curve = key.get("curve")
            if i + 1 == len(keys) or curve is None or curve == "linear":
                self.beziers.append("linear")
            elif curve == "stepped":
                self.beziers.append("stepped")
            else:
                t0, t1 = self.times[i], self.times[i + 1]
                v0, v1 = self.values[i], float(keys[i + 1].get(fields[component], neutral))
                if major == 3:
                    if isinstance(curve, list):
                        cx1, cy1, cx2, cy2 = curve
                    else:
                        cx1, cy1, cx2, cy2 = curve, key.get("c2", 0), key.get("c3", 1), key.get("c4", 1)
                    in_span = 0 <= cx1 <= 1 and 0 <= cx2 <= 1
                    handles = (t0 + cx1 * (t1 - t0), v0 + cy1 * (v1 - v0),
                               t0 + cx2 * (t1 - t0), v0 + cy2 * (v1 - v0))
                else:
                    cx1, cy1, cx2, cy2 = curve[4 * component:4 * component + 4]
                    written = (float(key.get("time", 0)), float(keys[i + 1].get("time", 0)))
                    in_span = all(written[0] <= cx <= written[1] for cx in (cx1, cx2))
                    # absolute handles clamped into the keys' times as read
                    handles = (min(max(cx1, t0), t1), cy1, min(max(cx2, t0), t1), cy2)
                if not in_span:
                    if major == 3:
                        raw = handles
                    else:
                        raw = (cx1, cy1, cx2, cy2)
                    self.beziers.append(("played", _played_samples(t0, v0, raw, t1, v1)))
                    continue
                self.beziers.append(handles)

    def keys(self):
        return self.times

    def at(self, t):
        if t < self.times[0]:
            return self.neutral
        i = max(k for k in range(len(self.times)) if self.times[k] <= t)
        if i + 1 == len(self.times):
            return self.values[i]
        t0, t1 = self.times[i], self.times[i + 1]
        v0, v1 = self.values[i], self.values[i + 1]
        kind = self.beziers[i]
        if kind == "stepped":
            return v0
        if kind == "linear":
            return v0 + (v1 - v0) * (t - t0) / (t1 - t0)
        if kind[0] == "played":
            samples = kind[1]
            if t <= t0:
                return v0
            k = next(k for k in range(1, len(samples)) if samples[k][0] >= t)
            (xa, ya), (xb, yb) = samples[k - 1], samples[k]
            return ya + (yb - ya) * (t - xa) / (xb - xa) if xb > xa else yb
        cx1, cy1, cx2, cy2 = kind

        def cubic(p0, p1, p2, p3, u):
            w = 1 - u
            return w * w * w * p0 + 3 * w * w * u * p1 + 3 * w * u * u * p2 + u * u * u * p3

        lo, hi = 0.0, 1.0
        for _ in range(200):
            mid = (lo + hi) / 2
            if cubic(t0, cx1, cx2, t1, mid) < t:
                lo = mid
            else:
                hi = mid
        return cubic(v0, cy1, cy2, v1, (lo + hi) / 2)


def _played_samples(t0, v0, handles, t1, v1):
    """The points (time, value) at u = 0, 0.1, ..., 1 of the Bezier from (t0, v0) through the
    handles to (t1, v1); the last is the next key itself."""
    cx1, cy1, cx2, cy2 = handles

    def cubic(p0, p1, p2, p3, u):
        w = 1 - u
        return w * w * w * p0 + 3 * w * w * u * p1 + 3 * w * u * u * p2 + u * u * u * p3

    points = [(cubic(t0, cx1, cx2, t1, k / 10), cubic(v0, cy1, cy2, v1, k / 10)) for k in range(10)]
    return points + [(t1, v1)]


def bone_values(doc):
    """{animation: {curve id: Timeline}} for every bone value timeline."""
    major = int(doc["skeleton"]["spine"].split(".")[0])
    fps = float(doc["skeleton"].get("fps", 30))
    kinds3 = {"rotate": ("rotate", ["angle"], [""]), "translate": ("translate", ["x", "y"], [".x", ".y"]),
              "scale": ("scale", ["x", "y"], [".x", ".y"]), "shear": ("shear", ["x", "y"], [".x", ".y"])}
    kinds4 = {"rotate": ("rotate", ["value"], [""])}
    for base in ("translate", "scale", "shear"):
        kinds4[base] = (base, ["x", "y"], [".x", ".y"])
        kinds4[base + "x"] = (base, ["value"], [".x"])
        kinds4[base + "y"] = (base, ["value"], [".y"])
    kinds = kinds3 if major == 3 else kinds4
    fps = float(doc["skeleton"].get("fps", 30))
    out = {}
    for name, animation in doc.get("animations", {}).items():
        curves = {}
        for bone, timelines in animation.get("bones", {}).items():
            for timeline, keys in timelines.items():
                if timeline not in kinds or not keys:
                    continue
                base, fields, suffixes = kinds[timeline]
                for c, suffix in enumerate(suffixes):
                    # in 3.x a scale key's missing x/y is 1 (3.8's documented default).
                    neutral = 1.0 if base == "scale" else 0.0
                    curves["%s/%s%s" % (bone, base, suffix)] = Timeline(keys, fields, c, neutral, major, fps)
        out[name] = curves
    return out


def duration(value):
    latest = 0.0
    if isinstance(value, list):
        for item in value:
            if isinstance(item, dict) and isinstance(item.get("time"), (int, float)):
                latest = max(latest, float(item["time"]))
            latest = max(latest, duration(item))
    elif isinstance(value, dict):
        for item in value.values():
            latest = max(latest, duration(item))
    return latest


def drawing_layout(doc, name, curves, on=ON, merge=True):
    """The drawings of an animation on the grid: (drawing_of_grid, starts, taus) with, per grid
    frame, the drawing shown; per drawing its first grid frame and its tau in seconds. Key poses
    are the keys' times rounded to frames, snapped to the grid (the first of several on one grid
    frame kept); with `merge` (koma's default, docs/semantics.md "Key poses") a time less than
    `on` grid frames after the pose before it, or before the last frame, joins that pose, and a
    segment of L frames gets max(1, L // on) drawings; without it ceil(L / on). Taus lie between
    the key poses' own times (the earliest key time that rounds to the pose's frame; the clip's
    ends as they are), the last drawing at the clip's end."""
    fps = float(doc["skeleton"].get("fps", 30))
    last = _round_half_away(duration(doc["animations"][name]) * fps)
    grid_count = int(math.floor(last * GRID_FPS / fps + 1e-9)) + 1
    last_grid = grid_count - 1
    source_keys = {0, last}
    own_time = {}  # per rounded frame, the earliest key time (frames) that rounds to it
    for timeline in curves.values():
        for t in timeline.keys():
            k = _round_half_away(t * fps)
            source_keys.add(k)
            own_time[k] = min(own_time.get(k, t * fps), t * fps)
    poses = []  # (grid frame, the pose's own time in frames)
    for k in sorted(source_keys):
        g = min(_round_half_away(k * GRID_FPS / fps), last_grid)
        if g == last_grid or (poses and poses[-1][0] == g):
            continue
        if merge and poses and (g - poses[-1][0] < on or last_grid - g < on):
            continue
        poses.append((g, own_time.get(k, k) if 0 < k < last else k))
    poses.append((last_grid, last))
    drawing_of_grid = [None] * grid_count
    starts, taus = [], []
    for (a, ta), (b, tb) in zip(poses, poses[1:]):
        length = b - a
        count = max(1, length // on) if merge else -(-length // on)
        q, r = divmod(length, count)
        start = a
        for j in range(count):
            hold = q + 1 if j < r else q
            starts.append(start)
            taus.append((ta + (tb - ta) * j / count) / fps)
            for g in range(start, start + hold):
                drawing_of_grid[g] = len(starts) - 1
            start += hold
    starts.append(last_grid)
    taus.append(last / fps)
    drawing_of_grid[last_grid] = len(starts) - 1
    return drawing_of_grid, starts, taus


def drawn_values(timeline, drawing_of_grid, taus):
    """Per drawing, the value a bone value shows: its keys to draw (first, last, and each key
    whose value turns or starts or ends a run of equal values) each in the drawing of the grid
    frame nearest its time; one per drawing (last, then first, then the largest change to a
    neighbouring key, the earlier of equals); a loser moves to the drawing before (it is earlier
    than the winner) or after, when no key falls there; the other drawings at their tau clamped
    between the drawn keys around them."""
    t, v = timeline.times, timeline.values
    keys = []  # (time, value, rank, swing)
    for i in range(len(t)):
        inc = v[i] - v[i - 1] if i > 0 else 0.0
        out = v[i + 1] - v[i] if i + 1 < len(t) else 0.0
        rank = 2 if i + 1 == len(t) else 1 if i == 0 else 0
        if rank or inc * out < 0 or ((inc == 0) != (out == 0)):
            keys.append((t[i], v[i], rank, max(abs(inc), abs(out))))
    count = len(taus)
    last_grid = len(drawing_of_grid) - 1

    def beats(k, c):
        return c is None or keys[k][2] > keys[c][2] or (keys[k][2] == keys[c][2] and keys[k][3] > keys[c][3])

    home, carried = [], [None] * count
    for k, key in enumerate(keys):
        g = min(max(math.ceil(key[0] * GRID_FPS - 0.5 - 1e-9), 0), last_grid)
        home.append(drawing_of_grid[g])
        if beats(k, carried[home[k]]):
            carried[home[k]] = k
    moved = list(carried)
    for k in range(len(keys)):
        w = carried[home[k]]
        if w == k:
            continue
        target = home[k] - 1 if keys[k][0] < keys[w][0] else home[k] + 1
        if 0 <= target < count and carried[target] is None and beats(k, moved[target]):
            moved[target] = k
    values = []
    for d in range(count):
        if moved[d] is not None:
            values.append(keys[moved[d]][1])
            continue
        before = [moved[e] for e in range(d) if moved[e] is not None]
        after = [moved[e] for e in range(d + 1, count) if moved[e] is not None]
        if before and taus[d] <= keys[before[-1]][0]:
            values.append(keys[before[-1]][1])
        elif after and taus[d] >= keys[after[0]][0]:
            values.append(keys[after[0]][1])
        else:
            values.append(timeline.at(taus[d]))
    return values


def check(before_doc, after_doc, animations, on=ON):
    """Raises AssertionError on the first mismatch; returns the number of values checked."""
    before_all, after_all = bone_values(before_doc), bone_values(after_doc)
    checked = 0
    for name in animations:
        before, after = before_all[name], after_all[name]
        assert sorted(before) == sorted(after), (name, sorted(before), sorted(after))
        drawing_of_grid, _, taus = drawing_layout(before_doc, name, before, on)
        fps = float(before_doc["skeleton"].get("fps", 30))
        clip_end = _round_half_away(duration(before_doc["animations"][name]) * fps) / fps
        for curve_id, timeline in before.items():
            out = after[curve_id]
            for k, t in enumerate(out.times):
                grid = t * GRID_FPS
                # Drawings start on the grid; a last key may hold the last drawing to the clip's
                # end (the animation's last frame, which need not be a grid time).
                assert abs(grid - round(grid)) < 1e-9 or (
                    k + 1 == len(out.times) and abs(t - clip_end) < 1e-9), (
                        name, curve_id, "key off the grid", t)
                if k + 1 < len(out.times):
                    assert out.beziers[k] == "stepped", (name, curve_id, k, out.beziers[k])
            shown = drawn_values(timeline, drawing_of_grid, taus)
            for g, drawing in enumerate(drawing_of_grid):
                want = shown[drawing]
                got = out.at(g / GRID_FPS)
                assert abs(got - want) <= 1e-6 * max(1.0, abs(want)), (
                    name, curve_id, "grid frame", g, "got", got, "want", want, "drawing", drawing,
                    "tau", taus[drawing])
                checked += 1
    return checked


def loop_closes(before_doc, after_doc, animation):
    """For every bone value whose input ends on the value it starts with, the output does too."""
    before, after = bone_values(before_doc)[animation], bone_values(after_doc)[animation]
    closed = 0
    for curve_id, timeline in before.items():
        if len(timeline.values) < 2 or timeline.values[0] != timeline.values[-1]:
            continue
        out = after[curve_id]
        assert abs(out.values[-1] - out.values[0]) <= 1e-9, (animation, curve_id, out.values[0], out.values[-1])
        closed += 1
    return closed


def drawings_in(doc, name, curve_id, begin, end):
    """Distinct output key times of one value in [begin, end) seconds."""
    return len([t for t in bone_values(doc)[name][curve_id].times if begin <= t < end - 1e-9])


if __name__ == "__main__":
    before_path, after_path = sys.argv[1], sys.argv[2]
    names = sys.argv[3:]
    before_doc, after_doc = (json.load(open(p, encoding="utf-8")) for p in (before_path, after_path))
    if not names:
        names = [n for n, c in bone_values(before_doc).items() if c]
    print("%s: %d values checked on the grid" % (after_path, check(before_doc, after_doc, names)))


# Slot attachment timelines (animations.<a>.slots.<slot>.attachment, the same in 3.x and 4.x:
# keys {"time": seconds (absent: 0), "name": attachment or null}); before the first key the
# slot shows its setup attachment (slots[].attachment).
def attachment_keys(doc, animation, slot):
    keys = doc["animations"].get(animation, {}).get("slots", {}).get(slot, {}).get("attachment", [])
    return [(float(k.get("time", 0)), k.get("name")) for k in keys]


def setup_attachment(doc, slot):
    for s in doc["slots"]:
        if s["name"] == slot:
            return s.get("attachment")
    raise KeyError(slot)


def attachment_at(doc, animation, slot, t):
    """The attachment the slot shows at t seconds: the last key at or before t."""
    shown = setup_attachment(doc, slot)
    for time, name in attachment_keys(doc, animation, slot):
        if time <= t + 1e-9:
            shown = name
    return shown


def check_attachment_keys(doc, animation, slot, names, grid_fps=GRID_FPS):
    """Keys on the grid (time * grid_fps whole), increasing, naming only `names`, one at 0 s,
    no two neighbours alike. Returns the keys."""
    keys = attachment_keys(doc, animation, slot)
    assert keys and keys[0][0] == 0, f"{slot}: no key at 0 s: {keys[:2]}"
    for i, (time, name) in enumerate(keys):
        assert name in names, f"{slot}[{i}]: {name!r} is not one of {names}"
        g = time * grid_fps
        assert abs(g - round(g)) < 1e-9, f"{slot}[{i}]: {time} s is not on the {grid_fps} fps grid"
        if i:
            assert time > keys[i - 1][0], f"{slot}[{i}]: time does not increase"
            assert name != keys[i - 1][1], f"{slot}[{i}]: the same drawing twice"
    return keys

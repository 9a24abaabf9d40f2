// Spine (Esoteric Software) skeleton JSON <-> one CurveSet per animation, keeping every field
// koma does not touch.
//
// Written from the published format (esotericsoftware.com/spine-json-format, the 3.7, 3.8 and
// 4.x pages); no runtime code is used. Versions read: 3.7, 3.8, 4.0, 4.1 and 4.2, from
// skeleton.spine ("3.8.99"); the file is written back in its own version, since the runtimes
// refuse a mismatch. Binary .skel files are not read.
//
// A bone timeline's value becomes one curve per value, with a readable id:
//   3.x  rotate {time, angle}        -> "<bone>/rotate"
//        translate|scale|shear {time, x, y} -> "<bone>/translate.x", "<bone>/translate.y", ...
//   4.x  rotate {time, value}        -> "<bone>/rotate"
//        translate|scale|shear {time, x, y} -> ".x" and ".y" curves as in 3.x
//        translatex|translatey|scalex|... {time, value} -> "<bone>/translate.x", ...
// Times are seconds (a missing time is 0); a missing value is 0, or 1 for scale. The curve on
// key i shapes the segment to key i + 1: absent (or "linear") linear, "stepped" held, else a
// cubic Bezier from key i through two handles to key i + 1, evaluated on its handles' times
// (x(u) = t solved for u, then y(u)):
//   3.7  "curve": [cx1, cy1, cx2, cy2]; 3.8 "curve": cx1, "c2": cy1 (default 0), "c3": cx2
//        (default 1), "c4": cy2 (default 1). Normalised: handle time t0 + cx (t1 - t0), handle
//        value v0 + cy (v1 - v0); one curve for both values of a translate key.
//   4.x  "curve": [cx1, cy1, cx2, cy2] per value (8 numbers for x and y), absolute: times in
//        seconds, values in the value's unit.
// A Bezier with a handle time outside its segment (the editor writes them) becomes the straight
// pieces Spine's runtimes play instead (formats/spine_played_bezier.h); the keys stay. Key
// times within 0.00005 s of a whole frame (Spine writes 4 decimals: 1/6 s is 0.1667) are that
// frame; handles are clamped into the segment between the keys' frames.
// Before its first key a timeline shows the setup pose (the runtimes' rule): the curve then
// starts at frame 0 with the neutral value (0; 1 for scale) stepped to the first key. At and
// after its last key it holds the last value.
#ifndef KOMA_FORMATS_SPINE_H_
#define KOMA_FORMATS_SPINE_H_

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/curves.h"

namespace koma::formats {

// Deepest JSON nesting ParseSpine accepts (a skeleton needs about 8: animations, deform
// timelines inside skins inside slots). Deeper input is refused before nlohmann parses it.
inline constexpr int kMaxSpineDepth = 64;

// Frames per second of the curves when skeleton.fps (nonessential data: the editor's dopesheet
// rate) is absent: Spine's default.
inline constexpr double kSpineDefaultFps = 30.0;

// One curve of a bone timeline.
struct SpineChannel {
  std::string bone;
  std::string timeline;  // its JSON name: "rotate", "translate", "translatex", ...
  int component = 0;     // 0: angle / value / x; 1: y
  // The timeline's first key is after 0 s, so the curve starts with the setup pose.
  bool from_setup = false;
};

struct SpineAnimation {
  std::string name;
  // Seconds: the latest key time of any of its timelines (bone, slot, event, deform, ...), as
  // the runtimes compute an animation's duration.
  double duration = 0.0;
  // Its bone value timelines as curves in frames (frame = t x fps), in file order (bones, then
  // each bone's timelines, then x before y); frame_count = round(duration x fps) + 1. No
  // curves when it has no such timeline.
  CurveSet curves;
  std::vector<SpineChannel> channels;  // channels[c] describes curves.curves[c]

  // Has bone values to retime over at least two frames.
  bool retimable() const { return !curves.curves.empty() && curves.frame_count >= 2; }
};

struct SpineFile {
  // The whole file as parsed, keys in file order: WriteSpine starts from it.
  nlohmann::ordered_json document;
  std::string version;  // skeleton.spine, e.g. "3.8.99"
  int major = 0;        // 3 or 4
  int minor = 0;
  double fps = kSpineDefaultFps;  // skeleton.fps when present
  std::vector<SpineAnimation> animations;  // in file order
};

// True when `text` looks like a Spine skeleton rather than a motion3.json: a JSON object whose
// first key is "skeleton" (Spine's exports put it first), or one that has a "skeleton" key and
// no "Meta" key anywhere in its text. Only a guess for choosing the reader; ParseSpine decides.
bool IsSpineJson(std::string_view text);

// Parses a Spine JSON skeleton. INVALID_ARGUMENT naming the JSON path and the value
// ("animations.walk.bones.torso.rotate[2].time: ...") for: malformed JSON (with the byte
// offset, and a hint when the bytes look like a binary .skel), nesting deeper than
// kMaxSpineDepth, a missing or unsupported skeleton.spine, bones that are not named objects,
// wrong types in bone timelines, keys whose times do not increase (also two keys on one frame
// by the 4-decimal rule), unknown curve kinds, Bezier arrays of the wrong length, handles too
// far out to evaluate in doubles, timelines naming a bone that is not in `bones`, a 3.x field
// (angle, c2..c4, a curve number) in a 4.x file, a 4.x field or timeline (value, translatex,
// ...) in a 3.x file, and the same curve keyed twice (translate and translatex on one bone).
// OUT_OF_RANGE when an animation is longer than an int counts frames. Timelines koma does not
// retime (slots, events, deform, constraints, inherit, ...) are kept, not checked.
absl::StatusOr<SpineFile> ParseSpine(std::string_view text);

// The index in file.animations of the animation named `name`; NOT_FOUND listing the names.
absl::StatusOr<int> FindSpineAnimation(const SpineFile& file, std::string_view name);

// Retimed curves of one animation: stepped[c] (when set) replaces curve c of
// file.animations[animation].curves, as stepped keyframes in frames.
struct SpineRetimed {
  int animation = 0;
  std::vector<std::optional<std::vector<CurvePoint>>> stepped;
};

// file.document with each retimed timeline's keys replaced by stepped keys: one key per point
// (for a two-value timeline, per point of either value, the other value read from its own
// points), time = frame / fps seconds, "curve": "stepped" on every key but the last, in the
// file's version's fields. A timeline whose new keys equal its old ones (already stepped, same
// times and values) keeps its old keys. Everything else keeps its value and position. Numbers
// that are whole are written as integers. Output: tab-indented, LF, a final newline.
// INVALID_ARGUMENT for an animation index out of range, a stepped count that is not the
// animation's curve count, or points that are not finite or do not strictly increase.
absl::StatusOr<std::string> WriteSpine(const SpineFile& file,
                                       const std::vector<SpineRetimed>& retimed);

// The same text the plain way: a copy of file.document with the timelines replaced, dumped by
// nlohmann. WriteSpine walks the document instead of copying it; this is the reference the
// tests compare it with.
absl::StatusOr<std::string> WriteSpineByDump(const SpineFile& file,
                                             const std::vector<SpineRetimed>& retimed);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_SPINE_H_

// ParseSpine: nlohmann parses the text into an ordered_json document (kept whole in SpineFile),
// then each animation's bone timelines are checked and converted to curves in frames.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/status_macros.h"
#include "formats/error_text.h"
#include "formats/json_text.h"
#include "formats/motion3_internal.h"
#include "formats/number_format.h"
#include "formats/spine.h"
#include "formats/spine_played_bezier.h"
#include "formats/text_encoding.h"

namespace koma::formats {
namespace {

using motion3_internal::DescribeJson;
using motion3_internal::FindMember;
using motion3_internal::MemberPath;
using motion3_internal::Json;
using motion3_internal::NumberAt;
using motion3_internal::PathError;
using motion3_internal::RequireArray;
using motion3_internal::RequireMember;
using motion3_internal::RequireObject;
using motion3_internal::StringAt;

// A time t x fps closer than this to an integer is that integer (frames), as for motion3.json.
constexpr double kSpineFrameSnap = 1e-6;

// Spine writes times rounded to 4 decimals: a key on frame 5 at 30 fps (1/6 s) is saved as
// 0.1667 s, frame 5.001. A key time within that rounding of a whole frame is that frame.
constexpr double kSpineTimeRounding = 0.00005;  // seconds: half the 4th decimal

double Frames(double seconds, double fps, double snap) {
  const double frames = seconds * fps;
  const double nearest = std::round(frames);
  return std::fabs(frames - nearest) <= snap ? nearest + 0.0 : frames;  // no -0
}

// Handle times: as motion3.json's, within kSpineFrameSnap of a frame.
double SecondsToFrames(double seconds, double fps) { return Frames(seconds, fps, kSpineFrameSnap); }

// Key times: within the 4 decimals' rounding (0.00005 s x fps frames), plus kSpineFrameSnap for
// the binary rounding of t x fps, of a frame (docs/formats.md).
double KeyTimeToFrames(double seconds, double fps) {
  return Frames(seconds, fps, kSpineTimeRounding * fps + kSpineFrameSnap);
}

// How a bone timeline's keys hold their values.
struct TimelineKind {
  const char* name;         // the timeline's JSON name
  const char* id_base;      // the curve id after "<bone>/": "rotate", "translate", ...
  const char* fields[2];    // the keys' value fields; fields[1] null for one value
  const char* suffixes[2];  // appended to the id: "" for one value, ".x"/".y"
  double neutral;           // the value that leaves the setup pose as it is
};

constexpr TimelineKind kSpine3Kinds[] = {
    {"rotate", "rotate", {"angle", nullptr}, {"", nullptr}, 0.0},
    {"translate", "translate", {"x", "y"}, {".x", ".y"}, 0.0},
    {"scale", "scale", {"x", "y"}, {".x", ".y"}, 1.0},
    {"shear", "shear", {"x", "y"}, {".x", ".y"}, 0.0},
};

constexpr TimelineKind kSpine4Kinds[] = {
    {"rotate", "rotate", {"value", nullptr}, {"", nullptr}, 0.0},
    {"translate", "translate", {"x", "y"}, {".x", ".y"}, 0.0},
    {"translatex", "translate", {"value", nullptr}, {".x", nullptr}, 0.0},
    {"translatey", "translate", {"value", nullptr}, {".y", nullptr}, 0.0},
    {"scale", "scale", {"x", "y"}, {".x", ".y"}, 1.0},
    {"scalex", "scale", {"value", nullptr}, {".x", nullptr}, 1.0},
    {"scaley", "scale", {"value", nullptr}, {".y", nullptr}, 1.0},
    {"shear", "shear", {"x", "y"}, {".x", ".y"}, 0.0},
    {"shearx", "shear", {"value", nullptr}, {".x", nullptr}, 0.0},
    {"sheary", "shear", {"value", nullptr}, {".y", nullptr}, 0.0},
};

int ValueCount(const TimelineKind& kind) { return kind.fields[1] == nullptr ? 1 : 2; }

const TimelineKind* FindKind(const std::string& name, int major) {
  if (major == 3) {
    for (const TimelineKind& kind : kSpine3Kinds) {
      if (name == kind.name) return &kind;
    }
  } else {
    for (const TimelineKind& kind : kSpine4Kinds) {
      if (name == kind.name) return &kind;
    }
  }
  return nullptr;
}

// Version-specific reading of one file.
struct Reader {
  int major = 3;
  int minor = 7;
  double fps = kSpineDefaultFps;
  std::string version;

  std::string VersionText() const { return absl::StrCat(major, ".", minor); }
  // A field of the other major version, found at `path`.
  absl::Status ForeignField(const std::string& path, const std::string& instead) const {
    return PathError(path, absl::StrCat("a Spine ", major == 3 ? "4.x" : "3.x",
                                        " field in a Spine ", VersionText(), " file (", version,
                                        "); ", instead));
  }
};

// One key's curve to the next key, in seconds and the value's unit.
struct KeyCurve {
  SegmentType type = SegmentType::kLinear;
  // For a Bezier: per value, cx1, cy1, cx2, cy2 (normalised in 3.x, absolute in 4.x).
  double bezier[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
};

// The paths below are callables that make the key's path: a string is only built for an
// error (a skeleton has thousands of keys; one path string per number cost more than reading
// it).
template <typename PathFn>
absl::StatusOr<double> OptionalNumber(const Json& key, const PathFn& path, const char* name,
                                      double fallback) {
  const Json* member = FindMember(key, name);
  if (member == nullptr) return fallback;
  if (member->is_number()) {
    const double number = member->get<double>();
    if (std::isfinite(number)) return number;
  }
  return NumberAt(*member, MemberPath(path(), name));  // the error
}

// NumberAt without a path unless it fails.
template <typename PathFn>
absl::StatusOr<double> NumberAtLazy(const Json& value, const PathFn& path) {
  if (value.is_number()) {
    const double number = value.get<double>();
    if (std::isfinite(number)) return number;
  }
  return NumberAt(value, path());
}

// The first of "c2", "c3", "c4" (in that order) that the object `key` has, or null: one pass
// over its members rather than a lookup each.
const char* FirstBezierNumberField(const Json& key) {
  static const char* const kFields[] = {"c2", "c3", "c4"};
  bool has[3] = {false, false, false};
  for (const auto& member : key.get_ref<const Json::object_t&>()) {
    const std::string& name = member.first;
    if (name.size() == 2 && name[0] == 'c' && name[1] >= '2' && name[1] <= '4') {
      has[name[1] - '2'] = true;
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (has[i]) return kFields[i];
  }
  return nullptr;
}

template <typename PathFn>
absl::StatusOr<KeyCurve> ReadKeyCurve(const Reader& reader, const Json& key, const PathFn& path,
                                      int values) {
  KeyCurve out;
  const char* number_field = FirstBezierNumberField(key);
  if (reader.major == 4 && number_field != nullptr) {
    return reader.ForeignField(MemberPath(path(), number_field),
                               "4.x keys hold a Bezier in one \"curve\" array");
  }
  const Json* curve = FindMember(key, "curve");
  const auto curve_path = [&path] { return MemberPath(path(), "curve"); };
  if (curve == nullptr) return out;
  if (curve->is_string()) {
    const std::string& kind = curve->get_ref<const std::string&>();
    if (kind == "stepped") {
      out.type = SegmentType::kStepped;
      return out;
    }
    if (kind == "linear") return out;
    return PathError(curve_path(),
                     absl::StrCat("unknown curve kind ", QuoteForError(kind),
                                  " (expected \"stepped\", \"linear\" or a Bezier's numbers)"));
  }
  out.type = SegmentType::kBezier;
  if (curve->is_number()) {
    if (reader.major == 4) {
      return reader.ForeignField(curve_path(),
                                 absl::StrCat("4.x keys hold a Bezier as an array of ",
                                              4 * values, " numbers"));
    }
    // 3.8: curve = cx1, c2 = cy1, c3 = cx2, c4 = cy2.
    KOMA_ASSIGN_OR_RETURN(out.bezier[0][0], NumberAtLazy(*curve, curve_path));
    KOMA_ASSIGN_OR_RETURN(out.bezier[0][1], OptionalNumber(key, path, "c2", 0.0));
    KOMA_ASSIGN_OR_RETURN(out.bezier[0][2], OptionalNumber(key, path, "c3", 1.0));
    KOMA_ASSIGN_OR_RETURN(out.bezier[0][3], OptionalNumber(key, path, "c4", 1.0));
  } else if (curve->is_array()) {
    const size_t expected = reader.major == 3 ? 4 : static_cast<size_t>(4 * values);
    if (curve->size() != expected) {
      return PathError(curve_path(),
                       absl::StrCat("a Bezier needs ", expected, " numbers",
                                    reader.major == 3 ? " (cx1, cy1, cx2, cy2)"
                                                      : " (cx1, cy1, cx2, cy2 per value)",
                                    ", got ", curve->size()));
    }
    for (size_t i = 0; i < expected; ++i) {
      KOMA_ASSIGN_OR_RETURN(out.bezier[i / 4][i % 4],
                            NumberAtLazy((*curve)[i], [&curve_path, i] {
                              return absl::StrCat(curve_path(), "[", i, "]");
                            }));
    }
    if (number_field != nullptr) {
      return PathError(MemberPath(path(), number_field),
                       "only with a number \"curve\" (3.8), not with a curve array");
    }
  } else {
    return PathError(curve_path(), absl::StrCat("expected \"stepped\" or a Bezier's numbers, got ",
                                              DescribeJson(*curve)));
  }
  if (reader.major == 3) {
    // One normalised curve for every value of the key.
    for (int k = 0; k < 4; ++k) out.bezier[1][k] = out.bezier[0][k];
  }
  return out;
}

// Appends to `segments` the segment from key `from` to key `to` (frames and values; t0 and t1
// their times as written, seconds), shaped by value v of the first key's `curve`. A Bezier
// whose handle times both lie within [t0, t1] is one Bezier segment, its handles clamped into
// [from, to] (against rounding, and when a key moved to its frame); one with a handle outside
// (the editor writes them) is the straight segments the runtimes play (spine_played_bezier.h).
template <typename PathFn>
absl::Status AppendSegment(const Reader& reader, const KeyCurve& curve, int v, double t0, double t1,
                           const CurvePoint& from, const CurvePoint& to, const PathFn& curve_path,
                           std::vector<CurveSegment>& segments) {
  CurveSegment segment;
  segment.type = curve.type;
  segment.end = to;
  if (segment.type != SegmentType::kBezier) {
    segments.push_back(segment);
    return absl::OkStatus();
  }
  // 3.x handles on the keys' frames when a key moved to its frame; else in seconds as before.
  const bool moved =
      from.frame != SecondsToFrames(t0, reader.fps) || to.frame != SecondsToFrames(t1, reader.fps);
  CurvePoint handles[2];
  bool in_span = true;
  for (int h = 0; h < 2; ++h) {
    const double cx = curve.bezier[v][2 * h], cy = curve.bezier[v][2 * h + 1];
    if (reader.major == 3) {  // normalised: cx of the way to the next key, cy of the change
      in_span = in_span && cx >= 0.0 && cx <= 1.0;
      handles[h].frame = moved ? from.frame + cx * (to.frame - from.frame)
                               : SecondsToFrames(t0 + cx * (t1 - t0), reader.fps);
      handles[h].value = from.value + cy * (to.value - from.value);
    } else {  // absolute: seconds and the value's unit
      in_span = in_span && t0 <= cx && cx <= t1;
      handles[h] = CurvePoint{SecondsToFrames(cx, reader.fps), cy};
    }
  }
  if (in_span) {
    for (int h = 0; h < 2; ++h) {
      segment.handles[h] =
          CurvePoint{std::clamp(handles[h].frame, from.frame, to.frame), handles[h].value};
    }
    segments.push_back(segment);
    return absl::OkStatus();
  }
  const CurvePoint controls[4] = {from, handles[0], handles[1], to};
  const std::vector<CurvePoint> played = SpinePlayedBezier(controls);
  if (played.empty()) {
    const double* b = curve.bezier[v];
    return PathError(curve_path(),
                     absl::StrCat("the handles (cx1, cy1, cx2, cy2) ", FormatDouble(b[0]), ", ",
                                  FormatDouble(b[1]), ", ", FormatDouble(b[2]), ", ",
                                  FormatDouble(b[3]), " are too far out to evaluate"));
  }
  for (size_t k = 0; k < played.size(); ++k) {
    CurveSegment straight;  // kLinear
    straight.end = played[k];
    // The points between the keys are the runtimes' samples, not keys: no key poses, no keys
    // to draw (the last point is the next key itself).
    straight.inserted = k + 1 < played.size();
    segments.push_back(straight);
  }
  return absl::OkStatus();
}

// The curves of one bone timeline (`keys` at `path`), appended to `animation`.
absl::Status ReadTimeline(const Reader& reader, const TimelineKind& kind, const std::string& bone,
                          const Json& keys, const std::string& path,
                          absl::flat_hash_set<std::string>& ids, SpineAnimation& animation) {
  KOMA_RETURN_IF_ERROR(RequireArray(keys, path));
  const int values = ValueCount(kind);
  std::string curve_ids[2];
  for (int v = 0; v < values; ++v) {
    curve_ids[v] = absl::StrCat(bone, "/", kind.id_base, kind.suffixes[v]);
    if (!ids.insert(curve_ids[v]).second) {
      return PathError(path, absl::StrCat("the curve ", QuoteForError(curve_ids[v]),
                                          " is keyed twice in this animation"));
    }
  }
  if (keys.empty()) return absl::OkStatus();  // nothing to retime; kept as it is
  std::vector<double> times;   // seconds, as written
  std::vector<double> frames;  // the keys' frames (KeyTimeToFrames)
  std::vector<double> key_values[2];
  std::vector<KeyCurve> curves;
  for (size_t i = 0; i < keys.size(); ++i) {
    const auto key_path = [&path, i] { return absl::StrCat(path, "[", i, "]"); };
    const Json& key = keys[i];
    if (!key.is_object()) return RequireObject(key, key_path());
    KOMA_ASSIGN_OR_RETURN(const double time, OptionalNumber(key, key_path, "time", 0.0));
    if (time < 0.0) {
      return PathError(MemberPath(key_path(), "time"),
                       absl::StrCat("expected seconds >= 0, got ", FormatDouble(time)));
    }
    if (!times.empty() && !(time > times.back())) {
      return PathError(MemberPath(key_path(), "time"),
                       absl::StrCat(FormatDouble(time), " is not after the previous key's ",
                                    FormatDouble(times.back()), " (keys must be in time order)"));
    }
    // The other version's value fields.
    const char* foreign = reader.major == 4 ? "angle" : (values == 1 ? "value" : nullptr);
    if (foreign != nullptr && FindMember(key, foreign) != nullptr) {
      return reader.ForeignField(MemberPath(key_path(), foreign),
                                 absl::StrCat("this key's value is \"", kind.fields[0], "\""));
    }
    for (int v = 0; v < values; ++v) {
      KOMA_ASSIGN_OR_RETURN(const double value,
                            OptionalNumber(key, key_path, kind.fields[v], kind.neutral));
      key_values[v].push_back(value);
    }
    KOMA_ASSIGN_OR_RETURN(KeyCurve curve, ReadKeyCurve(reader, key, key_path, values));
    const double frame = KeyTimeToFrames(time, reader.fps);
    if (!frames.empty() && !(frame > frames.back())) {  // both within 0.00005 s of one frame
      return PathError(MemberPath(key_path(), "time"),
                       absl::StrCat(FormatDouble(time), " s is frame ", FormatDouble(frame),
                                    ", as the previous key's ", FormatDouble(times.back()),
                                    " s (key times within 0.00005 s of a frame, Spine's 4 "
                                    "decimals, are that frame)"));
    }
    times.push_back(time);
    frames.push_back(frame);
    curves.push_back(curve);
  }
  for (int v = 0; v < values; ++v) {
    Curve out;
    out.id = curve_ids[v];
    SpineChannel channel{bone, kind.name, v, frames.front() > 0.0};
    const double first = frames.front();
    if (channel.from_setup) {
      out.start = CurvePoint{0.0, kind.neutral};
      CurveSegment to_first;
      to_first.type = SegmentType::kStepped;
      to_first.end = CurvePoint{first, key_values[v].front()};
      out.segments.push_back(to_first);
    } else {
      out.start = CurvePoint{first, key_values[v].front()};
    }
    for (size_t i = 0; i + 1 < times.size(); ++i) {
      const CurvePoint from = out.segments.empty() ? out.start : out.segments.back().end;
      KOMA_RETURN_IF_ERROR(AppendSegment(
          reader, curves[i], v, times[i], times[i + 1], from,
          CurvePoint{frames[i + 1], key_values[v][i + 1]},
          [&path, i] { return absl::StrCat(path, "[", i, "].curve"); }, out.segments));
    }
    animation.curves.curves.push_back(std::move(out));
    animation.channels.push_back(std::move(channel));
  }
  return absl::OkStatus();
}

// The latest "time" of any key under `value` (keys are objects in arrays), seconds.
double LatestKeyTime(const Json& value) {
  double latest = 0.0;
  if (value.is_array()) {
    for (const Json& item : value) {
      if (item.is_object()) {
        const Json* time = FindMember(item, "time");
        if (time != nullptr && time->is_number()) {
          const double t = time->get<double>();
          if (std::isfinite(t)) latest = std::max(latest, t);
        }
      }
      latest = std::max(latest, LatestKeyTime(item));
    }
  } else if (value.is_object()) {
    for (const auto& member : value.items()) latest = std::max(latest, LatestKeyTime(member.value()));
  }
  return latest;
}

absl::Status ReadVersion(const Json& document, Reader& reader) {
  KOMA_ASSIGN_OR_RETURN(const Json* skeleton, RequireMember(document, "", "skeleton"));
  KOMA_RETURN_IF_ERROR(RequireObject(*skeleton, "skeleton"));
  KOMA_ASSIGN_OR_RETURN(const Json* spine, RequireMember(*skeleton, "skeleton", "spine"));
  KOMA_ASSIGN_OR_RETURN(reader.version, StringAt(*spine, "skeleton.spine"));
  const std::string& v = reader.version;
  const bool known = v.size() >= 3 && v[1] == '.' && (v.size() == 3 || v[3] == '.') &&
                     ((v[0] == '3' && (v[2] == '7' || v[2] == '8')) ||
                      (v[0] == '4' && v[2] >= '0' && v[2] <= '2'));
  if (!known) {
    return PathError("skeleton.spine",
                     absl::StrCat(QuoteForError(v),
                                  " is not a Spine version koma reads (3.7, 3.8, 4.0, 4.1, 4.2)"));
  }
  reader.major = v[0] - '0';
  reader.minor = v[2] - '0';
  const Json* fps = FindMember(*skeleton, "fps");
  if (fps != nullptr) {
    KOMA_ASSIGN_OR_RETURN(reader.fps, NumberAt(*fps, "skeleton.fps"));
    if (!(reader.fps > 0.0) || reader.fps > 1e6) {
      return PathError("skeleton.fps",
                       absl::StrCat("expected frames per second in (0, 1e6], got ",
                                    FormatDouble(reader.fps)));
    }
  }
  return absl::OkStatus();
}

// The bones' names, checked as the Spine runtimes read a skeleton: every name unique (timelines
// name their bone), and a bone's parent, when it has one, an earlier bone (the editor writes
// parents first; the runtimes refuse a parent they have not read yet, which also refuses a bone
// that is its own parent and any cycle).
absl::StatusOr<absl::flat_hash_set<std::string>> ReadBoneNames(const Json& document) {
  KOMA_ASSIGN_OR_RETURN(const Json* bones, RequireMember(document, "", "bones"));
  KOMA_RETURN_IF_ERROR(RequireArray(*bones, "bones"));
  absl::flat_hash_map<std::string, size_t> index_of;  // name -> its index in bones
  for (size_t i = 0; i < bones->size(); ++i) {
    const std::string path = absl::StrCat("bones[", i, "]");
    KOMA_RETURN_IF_ERROR(RequireObject((*bones)[i], path));
    KOMA_ASSIGN_OR_RETURN(const Json* name, RequireMember((*bones)[i], path, "name"));
    KOMA_ASSIGN_OR_RETURN(std::string text, StringAt(*name, path + ".name"));
    if (const auto earlier = index_of.find(text); earlier != index_of.end()) {
      return PathError(path + ".name",
                       absl::StrCat(QuoteForError(text), " is also the name of bones[",
                                    earlier->second, "]: timelines name their bone, so names "
                                    "must be unique"));
    }
    if (const Json* parent = FindMember((*bones)[i], "parent"); parent != nullptr) {
      KOMA_ASSIGN_OR_RETURN(const std::string parent_name, StringAt(*parent, path + ".parent"));
      if (!index_of.contains(parent_name)) {
        return PathError(
            path + ".parent",
            absl::StrCat(QuoteForError(parent_name),
                         parent_name == text ? " is the bone itself" : " is no earlier bone",
                         ": a parent comes before its children in bones, as the Spine editor "
                         "writes them and its runtimes read them"));
      }
    }
    index_of.emplace(std::move(text), i);
  }
  absl::flat_hash_set<std::string> names;
  for (auto& [name, index] : index_of) names.insert(name);
  return names;
}

absl::StatusOr<SpineAnimation> ReadAnimation(const Reader& reader,
                                             const absl::flat_hash_set<std::string>& bones,
                                             const std::string& name, const Json& value) {
  const std::string path = absl::StrCat("animations.", name);
  KOMA_RETURN_IF_ERROR(RequireObject(value, path));
  SpineAnimation animation;
  animation.name = name;
  animation.duration = LatestKeyTime(value);
  const double last_frame = std::round(animation.duration * reader.fps);
  if (!(last_frame < static_cast<double>(INT_MAX) - 1)) {
    return absl::OutOfRangeError(absl::StrCat(path, ": ", FormatDouble(animation.duration),
                                              " s at ", FormatDouble(reader.fps),
                                              " fps is more frames than an int holds"));
  }
  animation.curves.fps = reader.fps;
  animation.curves.frame_count = static_cast<int>(last_frame) + 1;
  animation.curves.beziers_restricted = false;  // Beziers are solved on their handle times
  const Json* timelines = FindMember(value, "bones");
  if (timelines == nullptr) return animation;
  const std::string bones_path = path + ".bones";
  KOMA_RETURN_IF_ERROR(RequireObject(*timelines, bones_path));
  absl::flat_hash_set<std::string> ids;
  for (const auto& bone : timelines->items()) {
    const std::string bone_path = absl::StrCat(bones_path, ".", bone.key());
    if (!bones.contains(bone.key())) {
      return PathError(bone_path,
                       absl::StrCat("no bone named ", QuoteForError(bone.key()), " in bones"));
    }
    KOMA_RETURN_IF_ERROR(RequireObject(bone.value(), bone_path));
    for (const auto& timeline : bone.value().items()) {
      const std::string timeline_path = absl::StrCat(bone_path, ".", timeline.key());
      const TimelineKind* kind = FindKind(timeline.key(), reader.major);
      if (kind == nullptr && reader.major == 3 && FindKind(timeline.key(), 4) != nullptr) {
        return reader.ForeignField(timeline_path,
                                   "3.x keys x and y together in one translate, scale or shear "
                                   "timeline");
      }
      if (kind == nullptr) continue;  // inherit (4.2) and others: kept as they are
      KOMA_RETURN_IF_ERROR(
          ReadTimeline(reader, *kind, bone.key(), timeline.value(), timeline_path, ids, animation));
    }
  }
  return animation;
}

// A hint for bytes that are not JSON text: a binary .skel starts with a hash string's length.
bool LooksBinary(std::string_view text) {
  for (size_t i = 0; i < text.size() && i < 64; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x09 || (c > 0x0d && c < 0x20)) return true;
  }
  return false;
}

}  // namespace

bool IsSpineJson(std::string_view text) {
  size_t i = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // a UTF-8 byte order mark
  const auto skip_space = [&] {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' ||
                               text[i] == '\r')) {
      ++i;
    }
  };
  skip_space();
  if (i >= text.size() || text[i] != '{') return false;
  ++i;
  skip_space();
  if (text.compare(i, 10, "\"skeleton\"") == 0) return true;
  return text.find("\"skeleton\"") != std::string_view::npos &&
         text.find("\"Meta\"") == std::string_view::npos;
}

absl::StatusOr<SpineFile> ParseSpine(std::string_view text) {
  // A skeleton saved as UTF-16 or UTF-32 is named so, not taken for a binary .skel.
  KOMA_ASSIGN_OR_RETURN(text, SkipUtf8Bom(text));
  if (LooksBinary(text)) {
    return absl::InvalidArgumentError(
        "not JSON text: binary Spine .skel files are not read; export the skeleton as JSON "
        "(Spine's Export > JSON)");
  }
  SpineFile file;
  KOMA_ASSIGN_OR_RETURN(file.document, ParseJsonTextWithin(text, kMaxSpineDepth));
  if (!file.document.is_object()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "expected a JSON object at the top level, got ", DescribeJson(file.document)));
  }
  Reader reader;
  KOMA_RETURN_IF_ERROR(ReadVersion(file.document, reader));
  file.version = reader.version;
  file.major = reader.major;
  file.minor = reader.minor;
  file.fps = reader.fps;
  KOMA_ASSIGN_OR_RETURN(const absl::flat_hash_set<std::string> bones, ReadBoneNames(file.document));
  const Json* animations = FindMember(file.document, "animations");
  if (animations == nullptr) return file;
  KOMA_RETURN_IF_ERROR(RequireObject(*animations, "animations"));
  for (const auto& animation : animations->items()) {
    KOMA_ASSIGN_OR_RETURN(SpineAnimation read,
                          ReadAnimation(reader, bones, animation.key(), animation.value()));
    file.animations.push_back(std::move(read));
  }
  return file;
}

absl::StatusOr<int> FindSpineAnimation(const SpineFile& file, std::string_view name) {
  std::vector<std::string> names;
  for (size_t i = 0; i < file.animations.size(); ++i) {
    if (file.animations[i].name == name) return static_cast<int>(i);
    names.push_back(QuoteForError(file.animations[i].name));
  }
  return absl::NotFoundError(absl::StrCat(
      "no animation named ", QuoteForError(name), names.empty() ? " (the skeleton has none)"
                                                                : absl::StrCat(" (the skeleton has ", absl::StrJoin(names, ", "), ")")));
}

}  // namespace koma::formats

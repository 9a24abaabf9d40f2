// WriteSpine: the parsed document dumped as nlohmann dumps it (tab-indented), with the retimed
// bone timelines' keys written as stepped keys in their place. The document is not copied: the
// path down to the replaced timelines is walked here and every other value is dumped by
// nlohmann's own serializer, so the text is byte for byte what copying the document, replacing
// the timelines and dumping the copy gives (WriteSpineByDump, the reference the tests compare
// with), at about a third of the cost (profiled: copying and freeing the ~20,000-node document
// was half of WriteSpine).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/json_text.h"
#include "formats/motion3_internal.h"
#include "formats/number_format.h"
#include "formats/spine.h"

namespace koma::formats {
namespace {

using motion3_internal::Json;
using motion3_internal::PathError;

// Two key times closer than this (seconds) are the same time when comparing old keys with new.
constexpr double kSameTimeSeconds = 1e-9;

absl::Status CheckSteps(const std::vector<CurvePoint>& steps, const std::string& path) {
  if (steps.empty()) return PathError(path, "expected at least 1 stepped keyframe, got 0");
  for (size_t k = 0; k < steps.size(); ++k) {
    // The path is made only for an error (this runs for every new key).
    const auto here = [&] { return absl::StrCat(path, "[", k, "]"); };
    if (!std::isfinite(steps[k].frame) || !std::isfinite(steps[k].value)) {
      return PathError(
          here(), absl::StrCat("expected finite numbers, got frame ", FormatDouble(steps[k].frame),
                             ", value ", FormatDouble(steps[k].value)));
    }
    if (k > 0 && !(steps[k].frame > steps[k - 1].frame)) {
      return PathError(here() + ".frame", absl::StrCat(FormatDouble(steps[k].frame),
                                                     " is not after the previous keyframe's frame ",
                                                     FormatDouble(steps[k - 1].frame)));
    }
  }
  return absl::OkStatus();
}

// The stepped value at `frame`: the last point at or before it (the first before them all).
double StepValue(const std::vector<CurvePoint>& steps, double frame) {
  auto after = std::upper_bound(steps.begin(), steps.end(), frame,
                                [](double f, const CurvePoint& p) { return f < p.frame; });
  return after == steps.begin() ? steps.front().value : std::prev(after)->value;
}

// The value fields of a timeline's keys in `major`'s layout.
std::vector<const char*> ValueFields(const std::string& timeline, int major) {
  if (timeline == "rotate") return {major == 3 ? "angle" : "value"};
  if (timeline == "translate" || timeline == "scale" || timeline == "shear") return {"x", "y"};
  return {"value"};  // translatex, scaley, ... (4.x)
}

// One timeline's curves: indices into the animation's curves, by component.
struct TimelineCurves {
  std::string bone;
  std::string timeline;
  int curve[2] = {-1, -1};
};

// The original curve as keys (frame, value) when it is already stepped keys from its first key
// (no setup-pose prefix), else empty.
std::vector<CurvePoint> SteppedKeys(const Curve& curve, bool from_setup) {
  if (from_setup) return {};
  std::vector<CurvePoint> keys{curve.start};
  for (const CurveSegment& segment : curve.segments) {
    if (segment.type != SegmentType::kStepped) return {};
    keys.push_back(segment.end);
  }
  return keys;
}

bool SameKeys(const std::vector<CurvePoint>& a, const std::vector<CurvePoint>& b, double fps) {
  if (a.size() != b.size()) return false;
  for (size_t k = 0; k < a.size(); ++k) {
    if (std::fabs(a[k].frame - b[k].frame) > kSameTimeSeconds * fps) return false;
    if (a[k].value != b[k].value) return false;
  }
  return true;
}

// The new keys of one timeline: key times (frames) and, per value field, the value at each.
struct TimelineKeys {
  std::vector<const char*> fields;  // "angle" / "value", or "x" and "y"
  std::vector<double> frames;
  std::vector<double> values[2];
};

// The new keys of `group` in `animation`, or nullopt when they equal the old ones.
std::optional<TimelineKeys> NewKeys(const SpineFile& file, const SpineAnimation& animation,
                                    const SpineRetimed& retimed, const TimelineCurves& group) {
  TimelineKeys keys;
  keys.fields = ValueFields(group.timeline, file.major);
  std::vector<double>& frames = keys.frames;
  bool unchanged = true;
  for (size_t v = 0; v < keys.fields.size(); ++v) {
    const int c = group.curve[v];
    if (c < 0 || !retimed.stepped[c]) continue;
    const std::vector<CurvePoint>& steps = *retimed.stepped[c];
    for (const CurvePoint& p : steps) frames.push_back(p.frame);
    unchanged = unchanged && SameKeys(SteppedKeys(animation.curves.curves[c],
                                                  animation.channels[c].from_setup),
                                      steps, file.fps);
  }
  if (frames.empty() || unchanged) return std::nullopt;
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  for (size_t v = 0; v < keys.fields.size(); ++v) {
    const int c = group.curve[v];
    keys.values[v].reserve(frames.size());
    for (const double frame : frames) {
      double value = 0.0;
      if (c >= 0 && retimed.stepped[c]) {
        value = StepValue(*retimed.stepped[c], frame);
      } else if (c >= 0) {
        value = EvaluateCurve(animation.curves.curves[c], frame, false);
      }
      keys.values[v].push_back(value);
    }
  }
  return keys;
}

// The keys as JSON: {"time", the value fields, "curve": "stepped" but on the last}.
Json KeysJson(const TimelineKeys& keys, double fps) {
  Json out = Json::array();
  for (size_t k = 0; k < keys.frames.size(); ++k) {
    Json key = Json::object();
    key["time"] = JsonNumber(keys.frames[k] / fps);
    for (size_t v = 0; v < keys.fields.size(); ++v) key[keys.fields[v]] = JsonNumber(keys.values[v][k]);
    if (k + 1 < keys.frames.size()) key["curve"] = "stepped";
    out.push_back(std::move(key));
  }
  return out;
}

// Where the new keys go: animations.<name>.bones.<bone>.<timeline>, as a tree of the object
// members on that path; a leaf holds the keys written in place of the member's value.
struct ReplacementNode {
  absl::flat_hash_map<std::string, ReplacementNode> members;
  std::optional<TimelineKeys> keys;
};

// The replaced timelines of every retimed animation (a later entry for the same timeline wins,
// as the later assignment did when the document was edited), after checking `retimed`.
absl::Status CollectReplacements(const SpineFile& file, const std::vector<SpineRetimed>& retimed,
                                 ReplacementNode& root) {
  for (size_t r = 0; r < retimed.size(); ++r) {
    const SpineRetimed& one = retimed[r];
    if (one.animation < 0 || static_cast<size_t>(one.animation) >= file.animations.size()) {
      return absl::InvalidArgumentError(absl::StrCat("retimed[", r, "].animation: ", one.animation,
                                                     " is not an animation index (the file has ",
                                                     file.animations.size(), ")"));
    }
    const SpineAnimation& animation = file.animations[one.animation];
    if (one.stepped.size() != animation.curves.curves.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat("retimed[", r, "].stepped: expected one entry per curve of \"",
                       animation.name, "\" (", animation.curves.curves.size(), "), got ",
                       one.stepped.size()));
    }
    std::vector<TimelineCurves> groups;
    for (size_t c = 0; c < animation.channels.size(); ++c) {
      const SpineChannel& channel = animation.channels[c];
      if (one.stepped[c]) {
        KOMA_RETURN_IF_ERROR(
            CheckSteps(*one.stepped[c], absl::StrCat("retimed[", r, "].stepped[", c, "]")));
      }
      if (groups.empty() || groups.back().bone != channel.bone ||
          groups.back().timeline != channel.timeline) {
        groups.push_back(TimelineCurves{channel.bone, channel.timeline, {-1, -1}});
      }
      groups.back().curve[channel.component] = static_cast<int>(c);
    }
    for (const TimelineCurves& group : groups) {
      std::optional<TimelineKeys> keys = NewKeys(file, animation, one, group);
      if (!keys) continue;
      root.members["animations"]
          .members[animation.name]
          .members["bones"]
          .members[group.bone]
          .members[group.timeline]
          .keys = std::move(keys);
    }
  }
  return absl::OkStatus();
}

// Writes JSON text exactly as nlohmann's dump(1, '\t', false, replace) does, with the
// replacements in place: nlohmann's serializer writes every value off the replaced path.
class ReplacingWriter {
 public:
  ReplacingWriter(std::string& out, double fps)
      : out_(out),
        fps_(fps),
        serializer_(nlohmann::detail::output_adapter<char>(out), '\t',
                    Json::error_handler_t::replace) {}

  // `value` at nesting depth `indent` (tabs); `node` its replacements, or null for none.
  void Write(const Json& value, const ReplacementNode* node, unsigned indent) {
    if (node != nullptr && node->keys) {
      WriteKeys(*node->keys, indent);
      return;
    }
    if (node == nullptr || node->members.empty() || !value.is_object() || value.empty()) {
      Dump(value, indent);
      return;
    }
    // nlohmann's pretty object: "{\n", members "<indent+1>\"key\": value" joined by ",\n",
    // then "\n<indent>}".
    out_ += "{\n";
    size_t left = value.size();
    for (const auto& member : value.items()) {
      Indent(indent + 1);
      Dump(Json(member.key()), 0);  // quoted and escaped as nlohmann writes keys
      out_ += ": ";
      const auto child = node->members.find(member.key());
      Write(member.value(), child == node->members.end() ? nullptr : &child->second, indent + 1);
      out_ += --left > 0 ? ",\n" : "\n";
    }
    Indent(indent);
    out_ += '}';
  }

 private:
  void Indent(unsigned depth) { out_.append(depth, '\t'); }
  void Dump(const Json& value, unsigned indent) {
    serializer_.dump(value, /*pretty_print=*/true, /*ensure_ascii=*/false, 1, indent);
  }
  // JsonNumber(frame / fps) as nlohmann writes it. The retimed timelines of an animation
  // mostly share their drawings' times: each time is formatted once per call.
  void Time(double frame) {
    std::string& text = times_[frame];
    if (text.empty()) {
      const size_t at = out_.size();
      AppendJsonNumber(frame / fps_, out_);
      text.assign(out_, at, std::string::npos);
    } else {
      out_ += text;
    }
  }

  // What KeysJson(keys) dumps at `indent`, without building it. The text between the numbers
  // is the same for every key of a timeline: made once, appended whole (a few appends a key
  // rather than a dozen).
  void WriteKeys(const TimelineKeys& keys, unsigned indent) {
    const std::string key_indent(indent + 1, '\t');
    const std::string field_indent(indent + 2, '\t');
    // "<indent+1>{\n<indent+2>\"time\": "
    const std::string open = absl::StrCat(key_indent, "{\n", field_indent, "\"time\": ");
    std::string before_value[2];  // ",\n<indent+2>\"x\": "
    for (size_t v = 0; v < keys.fields.size(); ++v) {
      before_value[v] = absl::StrCat(",\n", field_indent, "\"", keys.fields[v], "\": ");
    }
    // ",\n<indent+2>\"curve\": \"stepped\"\n<indent+1>},\n" and the last key's "\n<indent+1>}\n"
    const std::string close =
        absl::StrCat(",\n", field_indent, "\"curve\": \"stepped\"\n", key_indent, "},\n");
    const std::string close_last = absl::StrCat("\n", key_indent, "}\n");
    out_ += "[\n";
    for (size_t k = 0; k < keys.frames.size(); ++k) {
      out_ += open;
      Time(keys.frames[k]);
      for (size_t v = 0; v < keys.fields.size(); ++v) {
        out_ += before_value[v];
        AppendJsonNumber(keys.values[v][k], out_);
      }
      out_ += k + 1 < keys.frames.size() ? close : close_last;
    }
    Indent(indent);
    out_ += ']';
  }


  std::string& out_;
  double fps_;
  absl::flat_hash_map<double, std::string> times_;  // frame -> its time's text
  nlohmann::detail::serializer<Json> serializer_;
};

// About the bytes the new keys take (~90 a one-value key at a bone timeline's depth, ~115 a
// two-value one), so the text is allocated once rather than grown through ~10 copies.
size_t NewKeyBytes(const ReplacementNode& node) {
  size_t bytes = 0;
  if (node.keys) bytes += node.keys->frames.size() * (64 + 32 * node.keys->fields.size());
  for (const auto& [key, child] : node.members) bytes += NewKeyBytes(child);
  return bytes;
}

absl::Status CheckFps(const SpineFile& file) {
  if (std::isfinite(file.fps) && file.fps > 0.0) return absl::OkStatus();
  return PathError("fps", absl::StrCat("expected a number > 0, got ", FormatDouble(file.fps)));
}

// Puts the replacements into `value` (the reference's way: edit a copy of the document).
void ReplaceIn(const ReplacementNode& node, double fps, Json& value) {
  for (const auto& [key, child] : node.members) {
    if (child.keys) {
      value[key] = KeysJson(*child.keys, fps);
    } else {
      ReplaceIn(child, fps, value[key]);
    }
  }
}

}  // namespace

absl::StatusOr<std::string> WriteSpine(const SpineFile& file,
                                       const std::vector<SpineRetimed>& retimed) {
  KOMA_RETURN_IF_ERROR(CheckFps(file));
  ReplacementNode root;
  KOMA_RETURN_IF_ERROR(CollectReplacements(file, retimed, root));
  std::string text;
  text.reserve(NewKeyBytes(root) + 4096);
  ReplacingWriter(text, file.fps).Write(file.document, &root, 0);
  text += '\n';
  return text;
}

absl::StatusOr<std::string> WriteSpineByDump(const SpineFile& file,
                                             const std::vector<SpineRetimed>& retimed) {
  KOMA_RETURN_IF_ERROR(CheckFps(file));
  ReplacementNode root;
  KOMA_RETURN_IF_ERROR(CollectReplacements(file, retimed, root));
  Json document = file.document;
  ReplaceIn(root, file.fps, document);
  // error_handler_t::replace: never throw on invalid UTF-8 (a parsed document has none).
  std::string text = document.dump(1, '\t', /*ensure_ascii=*/false, Json::error_handler_t::replace);
  text += '\n';
  return text;
}

}  // namespace koma::formats

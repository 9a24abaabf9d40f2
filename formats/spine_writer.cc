// WriteSpine: a copy of the parsed document with the retimed bone timelines' keys replaced by
// stepped keys, dumped by nlohmann.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

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
    const std::string here = absl::StrCat(path, "[", k, "]");
    if (!std::isfinite(steps[k].frame) || !std::isfinite(steps[k].value)) {
      return PathError(
          here, absl::StrCat("expected finite numbers, got frame ", FormatDouble(steps[k].frame),
                             ", value ", FormatDouble(steps[k].value)));
    }
    if (k > 0 && !(steps[k].frame > steps[k - 1].frame)) {
      return PathError(here + ".frame", absl::StrCat(FormatDouble(steps[k].frame),
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

// The new keys of `group` in `animation`, or nullopt when they equal the old ones.
std::optional<Json> NewKeys(const SpineFile& file, const SpineAnimation& animation,
                            const SpineRetimed& retimed, const TimelineCurves& group) {
  const std::vector<const char*> fields = ValueFields(group.timeline, file.major);
  std::vector<double> frames;
  bool unchanged = true;
  for (size_t v = 0; v < fields.size(); ++v) {
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
  Json keys = Json::array();
  for (size_t k = 0; k < frames.size(); ++k) {
    Json key = Json::object();
    key["time"] = JsonNumber(frames[k] / file.fps);
    for (size_t v = 0; v < fields.size(); ++v) {
      const int c = group.curve[v];
      double value = 0.0;
      if (c >= 0 && retimed.stepped[c]) {
        value = StepValue(*retimed.stepped[c], frames[k]);
      } else if (c >= 0) {
        value = EvaluateCurve(animation.curves.curves[c], frames[k], false);
      }
      key[fields[v]] = JsonNumber(value);
    }
    if (k + 1 < frames.size()) key["curve"] = "stepped";
    keys.push_back(std::move(key));
  }
  return keys;
}

}  // namespace

absl::StatusOr<std::string> WriteSpine(const SpineFile& file,
                                       const std::vector<SpineRetimed>& retimed) {
  if (!std::isfinite(file.fps) || !(file.fps > 0.0)) {
    return PathError("fps", absl::StrCat("expected a number > 0, got ", FormatDouble(file.fps)));
  }
  Json document = file.document;
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
      std::optional<Json> keys = NewKeys(file, animation, one, group);
      if (!keys) continue;
      document["animations"][animation.name]["bones"][group.bone][group.timeline] =
          *std::move(keys);
    }
  }
  // error_handler_t::replace: never throw on invalid UTF-8 (a parsed document has none).
  std::string text = document.dump(1, '\t', /*ensure_ascii=*/false, Json::error_handler_t::replace);
  text += '\n';
  return text;
}

}  // namespace koma::formats

// ValidateMouthOptions and ValidateEyeOptions: every message names the option's path and its
// value. Every option is checked, even one the request does not use (auto_blink.* while
// auto-blink is off), so a malformed request fails the same way whatever its switches.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/lip_blink.h"
#include "core/lip_blink_internal.h"
#include "core/status_macros.h"

namespace koma {
namespace {

absl::Status CheckRatio(double r, absl::string_view path, absl::string_view meaning) {
  if (std::isfinite(r) && r > 0.0 && r < 1.0) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat(path, ": ", r, " must be finite and in (0, 1) (", meaning, ")"));
}

// The closed and open levels, when given: finite, and closed below open when both are.
absl::Status CheckLevels(const std::optional<double>& min, const std::optional<double>& max) {
  if (min.has_value() && !std::isfinite(*min)) {
    return absl::InvalidArgumentError(absl::StrCat("min: ", *min, " must be finite"));
  }
  if (max.has_value() && !std::isfinite(*max)) {
    return absl::InvalidArgumentError(absl::StrCat("max: ", *max, " must be finite"));
  }
  if (min.has_value() && max.has_value() && !(*min < *max)) {
    return absl::InvalidArgumentError(
        absl::StrCat("min: ", *min, " must be less than max = ", *max));
  }
  return absl::OkStatus();
}

absl::Status CheckAutoBlink(const AutoBlinkOptions& a, int frame_count) {
  if (!std::isfinite(a.mean_interval_s) || a.mean_interval_s <= 0.0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "auto_blink.mean_interval_s: ", a.mean_interval_s, " must be finite and > 0 (seconds)"));
  }
  if (!std::isfinite(a.spread_s) || a.spread_s < 0.0 || a.spread_s >= a.mean_interval_s) {
    return absl::InvalidArgumentError(
        absl::StrCat("auto_blink.spread_s: ", a.spread_s,
                     " must be finite, >= 0 and < auto_blink.mean_interval_s = ", a.mean_interval_s,
                     " (seconds)"));
  }
  if (a.hold < 1 || a.hold > 3) {
    return absl::InvalidArgumentError(absl::StrCat(
        "auto_blink.hold: ", a.hold, " must be in [1, 3] (frames closed, then half-open)"));
  }
  return lip_blink_internal::CheckIntervals(a.keep, "auto_blink.keep", frame_count);
}

}  // namespace

namespace lip_blink_internal {

absl::Status CheckIntervals(const std::vector<FrameInterval>& intervals, absl::string_view path,
                            int frame_count) {
  for (size_t i = 0; i < intervals.size(); ++i) {
    const FrameInterval& v = intervals[i];
    const std::string name = absl::StrCat(path, "[", i, "]: [", v.begin, ", ", v.end, ")");
    if (v.end <= v.begin) {
      return absl::InvalidArgumentError(absl::StrCat(name, " is empty or reversed"));
    }
    if (v.begin < 0 || v.end > frame_count) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, " is outside [0, ", frame_count, ") (frame_count ", frame_count, ")"));
    }
    if (i > 0 && v.begin < intervals[i - 1].end) {
      const FrameInterval& p = intervals[i - 1];
      return absl::InvalidArgumentError(absl::StrCat(name, " begins before ", path, "[", i - 1,
                                                     "] = [", p.begin, ", ", p.end,
                                                     ") ends (sorted and disjoint)"));
    }
  }
  return absl::OkStatus();
}

}  // namespace lip_blink_internal

absl::Status ValidateMouthOptions(const MouthOptions& options, int frame_count) {
  if (options.frames_per_shape < 1) {
    return absl::InvalidArgumentError(absl::StrCat("frames_per_shape: ", options.frames_per_shape,
                                                   " must be >= 1 (frames each shape is held)"));
  }
  KOMA_RETURN_IF_ERROR(
      CheckRatio(options.mid_ratio, "mid_ratio", "M_mid = M_min + r (M_max - M_min)"));
  KOMA_RETURN_IF_ERROR(CheckLevels(options.min, options.max));
  return lip_blink_internal::CheckIntervals(options.speech, "speech", frame_count);
}

absl::Status ValidateEyeOptions(const EyeOptions& options, int frame_count) {
  KOMA_RETURN_IF_ERROR(
      CheckRatio(options.mid_ratio, "mid_ratio", "E_mid = E_min + r (E_max - E_min)"));
  const double delta = options.threshold;
  if (!std::isfinite(delta) || delta <= 0.0 || delta >= 0.5) {
    return absl::InvalidArgumentError(
        absl::StrCat("threshold: ", delta,
                     " must be finite and in (0, 0.5) (closed <= E_min + threshold range)"));
  }
  KOMA_RETURN_IF_ERROR(CheckLevels(options.min, options.max));
  if (!std::isfinite(options.fps) || options.fps <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("fps: ", options.fps, " must be finite and > 0 (frames per second)"));
  }
  return CheckAutoBlink(options.auto_blink, frame_count);
}

}  // namespace koma

// ValidateKomaUchiOptions: every message names the option's path and its value.
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/film_grid.h"
#include "core/koma_uchi.h"
#include "core/status_macros.h"

namespace koma {
namespace {

absl::Status CheckFramesPerDrawing(int n, const std::string& path) {
  if (n >= 1) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat(path, ": ", n, " must be >= 1 (frames each drawing is held)"));
}

absl::Status CheckStrength(double strength, const std::string& path) {
  if (std::isfinite(strength) && strength >= 1.0) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat(path, ": ", strength, " must be finite and >= 1 (1 = even spacing)"));
}

absl::Status CheckKeyFrames(const std::vector<int>& keys, int frame_count,
                            const std::string& path = "key_frames") {
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] < 0 || keys[i] > frame_count - 1) {
      return absl::InvalidArgumentError(absl::StrCat(path, "[", i, "]: ", keys[i],
                                                     " is outside [0, ", frame_count - 1,
                                                     "] (frame_count ", frame_count, ")"));
    }
    if (i > 0 && keys[i] <= keys[i - 1]) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, "[", i, "]: ", keys[i], " must be greater than ", path, "[", i - 1,
                       "] = ", keys[i - 1], " (strictly increasing)"));
    }
  }
  return absl::OkStatus();
}

absl::Status CheckCurveOverrides(const std::map<std::string, int>& overrides, const CurveSet& set) {
  std::set<std::string> ids;
  for (const Curve& curve : set.curves) ids.insert(curve.id);
  for (const auto& [id, n] : overrides) {
    const std::string path = absl::StrCat("curve_frames_per_drawing[\"", id, "\"]");
    if (ids.count(id) == 0) {
      return absl::InvalidArgumentError(absl::StrCat(path, ": no curve has this id"));
    }
    KOMA_RETURN_IF_ERROR(CheckFramesPerDrawing(n, path));
  }
  return absl::OkStatus();
}

absl::Status CheckSegmentOverrides(const std::vector<SegmentOverride>& overrides,
                                   int segment_count) {
  std::map<int, size_t> first_override;  // segment -> index of its override
  for (size_t i = 0; i < overrides.size(); ++i) {
    const SegmentOverride& o = overrides[i];
    const std::string path = absl::StrCat("segment_overrides[", i, "]");
    if (o.segment < 0 || o.segment >= segment_count) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".segment: ", o.segment, " is outside [0, ", segment_count, ") (",
                       segment_count, " segments between ", segment_count + 1, " key poses)"));
    }
    const auto [it, inserted] = first_override.emplace(o.segment, i);
    if (!inserted) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".segment: ", o.segment,
                                                     " is already overridden by "
                                                     "segment_overrides[",
                                                     it->second, "]"));
    }
    if (o.frames_per_drawing.has_value()) {
      KOMA_RETURN_IF_ERROR(
          CheckFramesPerDrawing(*o.frames_per_drawing, absl::StrCat(path, ".frames_per_drawing")));
    }
    if (o.tame.has_value()) KOMA_RETURN_IF_ERROR(CheckStrength(*o.tame, path + ".tame"));
    if (o.tsume.has_value()) KOMA_RETURN_IF_ERROR(CheckStrength(*o.tsume, path + ".tsume"));
  }
  return absl::OkStatus();
}

// timing_fps finite and <= 1000; with a grid, a source rate the grid can count and at least
// two grid frames (the first and the last key pose).
absl::Status CheckGrid(double timing_fps, const CurveSet& set) {
  KOMA_RETURN_IF_ERROR(ValidateTimingFps(timing_fps, "timing_fps"));
  if (timing_fps <= 0) return absl::OkStatus();
  KOMA_RETURN_IF_ERROR(ValidateSourceFps(set.fps, absl::StrCat("curves.fps: ", set.fps)));
  const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, timing_fps);
  if (grid && grid->GridFrameCount(set.frame_count) < 2) {
    return absl::OutOfRangeError(absl::StrCat(
        "curves.frame_count: ", set.frame_count, " frames at ", set.fps,
        " fps span less than 2 frames of the ", timing_fps,
        " fps film grid (timing_fps); send a longer clip, or timing_fps: 0 to count in source "
        "frames"));
  }
  return absl::OkStatus();
}

// Names non-empty, unique and not the default group's; at least one id pattern, none empty;
// the group's own n, strengths and key poses as the request's are checked.
absl::Status CheckGroups(const std::vector<CurveTimingGroup>& groups, int frame_count) {
  std::map<std::string, size_t> first_of_name;
  for (size_t g = 0; g < groups.size(); ++g) {
    const CurveTimingGroup& group = groups[g];
    const std::string path = absl::StrCat("timing_groups[", g, "]");
    if (group.name.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".name: required, not set"));
    }
    if (group.name == kDefaultTimingGroupName) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".name: \"", group.name,
                       "\" is the default group's (curves no group matches); choose another"));
    }
    const auto [it, inserted] = first_of_name.emplace(group.name, g);
    if (!inserted) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".name: \"", group.name,
                                                     "\" is already timing_groups[", it->second,
                                                     "]'s"));
    }
    if (group.ids.empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ".ids: empty (give curve ids or patterns such as \"ParamHair*\")"));
    }
    for (size_t i = 0; i < group.ids.size(); ++i) {
      if (group.ids[i].empty()) {
        return absl::InvalidArgumentError(absl::StrCat(path, ".ids[", i, "]: empty"));
      }
    }
    if (group.frames_per_drawing.has_value()) {
      KOMA_RETURN_IF_ERROR(
          CheckFramesPerDrawing(*group.frames_per_drawing, path + ".frames_per_drawing"));
    }
    if (group.tame.has_value()) KOMA_RETURN_IF_ERROR(CheckStrength(*group.tame, path + ".tame"));
    if (group.tsume.has_value()) {
      KOMA_RETURN_IF_ERROR(CheckStrength(*group.tsume, path + ".tsume"));
    }
    KOMA_RETURN_IF_ERROR(CheckKeyFrames(group.key_frames, frame_count, path + ".key_frames"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status ValidateKomaUchiOptions(const KomaUchiOptions& options, const CurveSet& set) {
  KOMA_RETURN_IF_ERROR(CheckFramesPerDrawing(options.frames_per_drawing, "frames_per_drawing"));
  KOMA_RETURN_IF_ERROR(CheckStrength(options.tame, "tame"));
  KOMA_RETURN_IF_ERROR(CheckStrength(options.tsume, "tsume"));
  KOMA_RETURN_IF_ERROR(CheckKeyFrames(options.key_frames, set.frame_count));
  KOMA_RETURN_IF_ERROR(CheckCurveOverrides(options.curve_frames_per_drawing, set));
  KOMA_RETURN_IF_ERROR(CheckGrid(options.timing_fps, set));
  KOMA_RETURN_IF_ERROR(CheckGroups(options.groups, set.frame_count));
  // Segments exist only once the key poses are known (they are valid by now): the default
  // group's, from its own curves.
  const std::vector<int> body = GroupMembers(options, set).back();
  const int segment_count =
      static_cast<int>(
          KeyPosesOnGrid(options, set, options.groups.empty() ? nullptr : &body).grid.size()) -
      1;
  return CheckSegmentOverrides(options.segment_overrides, segment_count);
}

absl::Status CheckGivenGroupTiming(const GivenGroupTiming& given, int frame_count,
                                   int counted_frames, absl::string_view field) {
  const int length = static_cast<int>(given.taus.size());
  if (length != counted_frames) {
    return absl::InvalidArgumentError(absl::StrCat(
        field, ": ", length, " values, but the clip has ", counted_frames,
        counted_frames == frame_count ? " frames" : " grid frames", " (one tau per frame)"));
  }
  const double last = static_cast<double>(frame_count - 1);
  for (int g = 0; g < length; ++g) {
    const double tau = given.taus[static_cast<size_t>(g)];
    if (!std::isfinite(tau) || tau < 0.0) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, "[", g, "]: ", tau, " must be finite and >= 0 (source frames)"));
    }
    if (tau > last) {
      return absl::InvalidArgumentError(absl::StrCat(field, "[", g, "]: ", tau,
                                                     " is past the clip's last frame ",
                                                     frame_count - 1));
    }
  }
  return absl::OkStatus();
}

}  // namespace koma

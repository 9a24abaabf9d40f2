// Validation half of server/lip_blink_request.h.
#include <algorithm>
#include <set>
#include <optional>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "convert/field_error.h"
#include "core/lip_blink_given.h"
#include "core/lip_blink_grid.h"
#include "core/status_macros.h"
#include "server/curve_convert.h"
#include "server/lip_blink_request.h"

namespace koma::server {
namespace {

constexpr const char* kDefaultMouthIds[] = {"ParamMouthOpenY"};
constexpr const char* kDefaultEyeIds[] = {"ParamEyeLOpen", "ParamEyeROpen"};

using convert::Prefixed;

int IndexOf(const CurveSet& set, const std::string& id) {
  for (size_t i = 0; i < set.curves.size(); ++i) {
    if (set.curves[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

// Given ids must name curves, once each, and no curve may be both mouth and eye (`taken`).
template <size_t N>
absl::StatusOr<std::vector<int>> ResolveIds(
    const google::protobuf::RepeatedPtrField<std::string>& ids, const char* const (&defaults)[N],
    absl::string_view path, const CurveSet& set, absl::string_view set_name,
    std::set<int>& taken) {
  std::vector<int> indices;
  if (ids.empty()) {
    for (const char* id : defaults) {
      const int index = IndexOf(set, id);
      if (index >= 0 && taken.insert(index).second) indices.push_back(index);
    }
    return indices;
  }
  for (int i = 0; i < ids.size(); ++i) {
    const int index = IndexOf(set, ids[i]);
    if (index < 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, "[", i, "]: \"", ids[i], "\" is not a curve of ", set_name));
    }
    if (!taken.insert(index).second) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, "[", i, "]: \"", ids[i], "\" is already a mouth or eye curve"));
    }
    indices.push_back(index);
  }
  return indices;
}

std::vector<FrameInterval> Intervals(
    const google::protobuf::RepeatedPtrField<v1::FrameInterval>& in) {
  std::vector<FrameInterval> out;
  for (const v1::FrameInterval& i : in) out.push_back({i.begin(), i.end()});
  return out;
}

}  // namespace

absl::StatusOr<MouthOptions> MouthOptionsFromProto(const v1::MouthSettings& in, int frame_count) {
  MouthOptions out;
  switch (in.mode()) {
    case v1::MOUTH_MODE_UNSPECIFIED:
    case v1::MOUTH_RANDOM:
      out.mode = MouthMode::kRandom;
      break;
    case v1::MOUTH_FOLLOW:
      out.mode = MouthMode::kFollow;
      break;
    default:
      return absl::InvalidArgumentError(absl::StrCat("mouth.mode: ", static_cast<int>(in.mode()),
                                                     " is not a MouthMode (1 RANDOM, 2 FOLLOW)"));
  }
  if (in.has_frames_per_shape()) out.frames_per_shape = in.frames_per_shape();
  if (in.has_mid_ratio()) out.mid_ratio = in.mid_ratio();
  if (in.has_min()) out.min = in.min();
  if (in.has_max()) out.max = in.max();
  out.speech = Intervals(in.speech());
  out.detect_speech = in.speech().empty();  // given intervals stay given, even if a grid drops them
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateMouthOptions(out, frame_count), "mouth."));
  return out;
}

absl::StatusOr<EyeOptions> EyeOptionsFromProto(const v1::EyeSettings& in, double fps, int frame_count) {
  EyeOptions out;
  out.fps = fps;
  if (in.has_mid_ratio()) out.mid_ratio = in.mid_ratio();
  if (in.has_threshold()) out.threshold = in.threshold();
  if (in.has_min()) out.min = in.min();
  if (in.has_max()) out.max = in.max();
  if (in.has_linked()) out.linked = in.linked();
  const v1::AutoBlink& auto_blink = in.auto_blink();
  out.auto_blink.enabled = auto_blink.enabled();
  if (auto_blink.has_mean_interval_s())
    out.auto_blink.mean_interval_s = auto_blink.mean_interval_s();
  // Unset spread: 1 s, or a quarter of a short mean, so `--auto-blink 0.8` alone is valid.
  out.auto_blink.spread_s = auto_blink.has_spread_s()
                                ? auto_blink.spread_s()
                                : std::min(1.0, out.auto_blink.mean_interval_s / 4.0);
  if (auto_blink.has_hold()) out.auto_blink.hold = auto_blink.hold();
  out.auto_blink.keep = Intervals(auto_blink.keep());
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateEyeOptions(out, frame_count), "eyes."));
  return out;
}

namespace {

// The film grid of timing_fps (unset: 24): checked, and the mouth and eye options moved onto
// it (they were checked on the source frames, where their intervals are given).
absl::Status ConvertGrid(double timing_fps, const RequestLimits& limits, LipBlinkJob* job) {
  KOMA_RETURN_IF_ERROR(ValidateTimingFps(timing_fps, "timing_fps"));
  if (timing_fps <= 0) return absl::OkStatus();
  KOMA_RETURN_IF_ERROR(ValidateSourceFps(job->set.fps, absl::StrCat("curves.fps: ", job->set.fps)));
  job->grid = FilmGrid::Make(job->set.fps, timing_fps);
  if (!job->grid) return absl::OkStatus();
  const int frames = job->grid->GridFrameCount(job->set.frame_count);
  if (frames < 2) {
    return absl::OutOfRangeError(
        absl::StrCat("curves.frame_count: ", job->set.frame_count, " frames at ", job->set.fps,
                     " fps span less than 2 frames of the ", timing_fps,
                     " fps film grid (timing_fps); send "
                     "a longer clip, or timing_fps: 0 to count in source frames"));
  }
  KOMA_RETURN_IF_ERROR(CheckGridValues(
      "curves", frames, timing_fps,
      static_cast<int64_t>(job->mouth_curves.size() + job->eye_curves.size()), "curves", limits));
  job->grid_frames = frames;
  job->mouth.speech = IntervalsOnGrid(job->mouth.speech, *job->grid, frames);
  job->eyes.auto_blink.keep = IntervalsOnGrid(job->eyes.auto_blink.keep, *job->grid, frames);
  job->eyes.fps = timing_fps;
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateMouthOptions(job->mouth, frames), "mouth."));
  return Prefixed(ValidateEyeOptions(job->eyes, frames), "eyes.");
}

}  // namespace

absl::StatusOr<LipBlinkJob> LipBlinkJobFor(CurveSet set, const v1::MouthSettings& mouth,
                                           const v1::EyeSettings& eyes,
                                           std::optional<uint64_t> seed,
                                           std::optional<double> timing_fps,
                                           const RequestLimits& limits, bool need_curves,
                                           absl::string_view set_name) {
  LipBlinkJob job;
  job.set = std::move(set);
  std::set<int> taken;
  KOMA_ASSIGN_OR_RETURN(job.mouth_curves, ResolveIds(mouth.ids(), kDefaultMouthIds, "mouth.ids",
                                                     job.set, set_name, taken));
  KOMA_ASSIGN_OR_RETURN(job.eye_curves, ResolveIds(eyes.ids(), kDefaultEyeIds, "eyes.ids",
                                                   job.set, set_name, taken));
  if (need_curves && job.mouth_curves.empty() && job.eye_curves.empty()) {
    return absl::InvalidArgumentError(
        "mouth.ids, eyes.ids: no mouth or eye curve to convert (none named, and the set has "
        "none of ParamMouthOpenY, ParamEyeLOpen, ParamEyeROpen)");
  }
  KOMA_ASSIGN_OR_RETURN(job.mouth, MouthOptionsFromProto(mouth, job.set.frame_count));
  KOMA_ASSIGN_OR_RETURN(job.eyes, EyeOptionsFromProto(eyes, job.set.fps, job.set.frame_count));
  KOMA_RETURN_IF_ERROR(ConvertGrid(timing_fps.value_or(kDefaultTimingFps), limits, &job));
  if (seed) job.seed = *seed;
  return job;
}

namespace {

// The index of curve `id` in `curves` (job.mouth_curves or eye_curves), or -1.
int TrackOf(const LipBlinkJob& job, const std::vector<int>& curves, const std::string& id) {
  for (size_t i = 0; i < curves.size(); ++i) {
    if (job.set.curves[static_cast<size_t>(curves[i])].id == id) return static_cast<int>(i);
  }
  return -1;
}

std::string IdsOf(const LipBlinkJob& job, const std::vector<int>& curves) {
  std::string ids;
  for (int c : curves) absl::StrAppend(&ids, ids.empty() ? "" : ", ", job.set.curves[static_cast<size_t>(c)].id);
  return ids.empty() ? "none" : ids;
}

// Every track of `curves` given once, by id: per track its index into the given list.
template <typename Given>
absl::StatusOr<std::vector<int>> MatchTracks(
    const LipBlinkJob& job, const std::vector<int>& curves,
    const google::protobuf::RepeatedPtrField<Given>& given, absl::string_view path,
    absl::string_view kind) {
  std::vector<int> of_track(curves.size(), -1);
  for (int i = 0; i < given.size(); ++i) {
    const int track = TrackOf(job, curves, given[i].id());
    if (track < 0) {
      return absl::InvalidArgumentError(absl::StrCat(path, "[", i, "].id: \"", given[i].id(),
                                                     "\" is not a ", kind, " curve (they are ",
                                                     IdsOf(job, curves), ")"));
    }
    if (of_track[track] >= 0) {
      return absl::InvalidArgumentError(absl::StrCat(path, "[", i, "].id: \"", given[i].id(),
                                                     "\" is already ", path, "[",
                                                     of_track[track], "]"));
    }
    of_track[track] = i;
  }
  for (size_t t = 0; t < curves.size(); ++t) {
    if (of_track[t] < 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          path, ": no timing for ", kind, " curve \"", job.set.curves[static_cast<size_t>(curves[t])].id,
          "\"; give every ", kind, " curve one, or none to time them as usual"));
    }
  }
  return of_track;
}

// LipBlinkRequest.given_timing into the job, on the frames holds count.
absl::Status ConvertGivenTiming(const v1::GivenLipBlinkTiming& given, LipBlinkJob& job) {
  const int frames = job.grid ? job.grid_frames : job.set.frame_count;
  if (given.mouths_size() > 0) {
    KOMA_ASSIGN_OR_RETURN(const std::vector<int> of_track,
                          MatchTracks(job, job.mouth_curves, given.mouths(),
                                      "given_timing.mouths", "mouth"));
    job.given_mouths.emplace();
    for (int i : of_track) {
      const v1::GivenMouthTiming& track = given.mouths(i);
      const std::string path = absl::StrCat("given_timing.mouths[", i, "].holds");
      std::vector<MouthHold> holds;
      for (int h = 0; h < track.holds_size(); ++h) {
        const v1::MouthHold& in = track.holds(h);
        MouthHold out{in.begin(), in.length(), MouthShape::kClosed};
        switch (in.shape()) {
          case v1::MOUTH_CLOSED:
            break;
          case v1::MOUTH_MID:
            out.shape = MouthShape::kMid;
            break;
          case v1::MOUTH_OPEN:
            out.shape = MouthShape::kOpen;
            break;
          default:
            return absl::InvalidArgumentError(absl::StrCat(
                path, "[", h, "].shape: ", static_cast<int>(in.shape()),
                " is not a mouth drawing (1 MOUTH_CLOSED, 2 MOUTH_MID, 3 MOUTH_OPEN)"));
        }
        holds.push_back(out);
      }
      KOMA_RETURN_IF_ERROR(ValidateGivenHolds(holds, frames, path));
      job.given_mouths->push_back(std::move(holds));
    }
  }
  if (given.eyes_size() > 0) {
    KOMA_ASSIGN_OR_RETURN(const std::vector<int> of_track,
                          MatchTracks(job, job.eye_curves, given.eyes(), "given_timing.eyes",
                                      "eye"));
    job.given_eyes.emplace();
    for (int i : of_track) {
      std::vector<Blink> blinks;
      for (const v1::Blink& in : given.eyes(i).blinks()) {
        blinks.push_back({in.closing_begin(), in.closed_begin(), in.closed_end(), in.open_span(),
                          in.hold(), in.automatic()});
      }
      KOMA_RETURN_IF_ERROR(
          ValidateGivenBlinks(blinks, frames, absl::StrCat("given_timing.eyes[", i, "].blinks")));
      job.given_eyes->push_back(std::move(blinks));
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<LipBlinkJob> ValidateLipBlinkRequest(const v1::LipBlinkRequest& request,
                                                    const RequestLimits& limits) {
  if (!request.has_curves()) return absl::InvalidArgumentError("curves: required, not set");
  KOMA_ASSIGN_OR_RETURN(CurveSet set, CurveSetFromProto(request.curves(), "curves", limits));
  KOMA_ASSIGN_OR_RETURN(
      LipBlinkJob job,
      LipBlinkJobFor(std::move(set), request.mouth(), request.eyes(),
                     request.has_seed() ? std::optional<uint64_t>(request.seed()) : std::nullopt,
                     request.has_timing_fps() ? std::optional<double>(request.timing_fps())
                                              : std::nullopt,
                     limits, /*need_curves=*/true, "the request"));
  if (request.has_given_timing()) {
    KOMA_RETURN_IF_ERROR(ConvertGivenTiming(request.given_timing(), job));
  }
  return job;
}

}  // namespace koma::server

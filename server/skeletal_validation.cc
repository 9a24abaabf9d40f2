// Validation half of server/skeletal_request.h: proto fields -> core types, every field
// checked before any work, errors naming the field path and the value.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "absl/strings/str_cat.h"
#include "convert/field_error.h"
#include "core/film_grid.h"
#include "core/given_skeletal_timing.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"
#include "server/skeletal_request.h"

namespace koma::server {
namespace {

using convert::Prefixed;

absl::StatusOr<Skeleton> ConvertSkeleton(const v1::Skeleton& proto, const RequestLimits& limits) {
  if (proto.joints_size() == 0) {
    return absl::InvalidArgumentError("motion.skeleton.joints: the skeleton has no joints");
  }
  if (proto.joints_size() > limits.max_joints) {
    return absl::ResourceExhaustedError(
        absl::StrCat("motion.skeleton.joints: ", proto.joints_size(),
                     " joints exceeds the server limit --max_joints=", limits.max_joints));
  }
  Skeleton skeleton;
  skeleton.joints.resize(proto.joints_size());
  for (int i = 0; i < proto.joints_size(); ++i) {
    const v1::Joint& in = proto.joints(i);
    Joint& out = skeleton.joints[i];
    out.name = in.name();
    out.parent = in.parent();
    out.offset = {in.offset().x(), in.offset().y(), in.offset().z()};
    for (const v1::Vec3& site : in.end_sites())
      out.end_sites.push_back({site.x(), site.y(), site.z()});
    out.channels.reserve(static_cast<size_t>(in.channels_size()));
    for (int c = 0; c < in.channels_size(); ++c) {
      absl::StatusOr<ChannelKind> kind = ParseChannelName(in.channels(c));
      if (!kind.ok()) {
        return Prefixed(kind.status(),
                        absl::StrCat("motion.skeleton.joints[", i, "].channels[", c, "]: "));
      }
      out.channels.push_back(*kind);
    }
  }
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateSkeleton(skeleton), "motion.skeleton."));
  return skeleton;
}

absl::Status CheckTiming(const v1::SkeletalMotion& motion) {
  if (!std::isfinite(motion.frame_time()) || motion.frame_time() <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("motion.frame_time: ", motion.frame_time(), " s must be finite and > 0"));
  }
  if (motion.frame_count() < 2) {
    return absl::InvalidArgumentError(absl::StrCat("motion.frame_count: ", motion.frame_count(),
                                                   " frames, retiming needs at least 2"));
  }
  return absl::OkStatus();
}

// Size limit first, then the exact count, then every value finite.
// `per_frame` is `count` `unit` (e.g. 31 " joints x 3 coordinates"), for the message.
absl::Status CheckValues(const google::protobuf::RepeatedField<double>& values,
                         absl::string_view field, int frame_count, int per_frame, int count,
                         absl::string_view unit, int64_t work_per_frame,
                         const RequestLimits& limits) {
  const int64_t work = static_cast<int64_t>(frame_count) * work_per_frame;
  if (work > limits.max_values) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "motion: ", frame_count, " frames x ", work_per_frame, " values per frame = ", work,
        " exceeds the server limit --max_values=", limits.max_values));
  }
  const int64_t expected = static_cast<int64_t>(frame_count) * per_frame;
  if (values.size() != expected) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected ", expected, " values (",
                                                   frame_count, " frames x ", count, unit,
                                                   "), got ", values.size()));
  }
  if (AllFinite(absl::MakeConstSpan(values.data(), values.size()))) return absl::OkStatus();
  for (int i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      return absl::InvalidArgumentError(absl::StrCat(field, "[", i, "]: ", values[i],
                                                     " is not finite (frame ", i / per_frame,
                                                     ", value ", i % per_frame, ")"));
    }
  }
  return absl::OkStatus();
}

absl::Status CheckMotionData(const v1::SkeletalMotion& motion, const Skeleton& skeleton,
                             const RequestLimits& limits, bool* channel_form) {
  const int joints = static_cast<int>(skeleton.joints.size());
  const int64_t position_values = 3LL * joints;
  switch (motion.data_case()) {
    case v1::SkeletalMotion::kChannels: {
      *channel_form = true;
      const int channels = ChannelCount(skeleton);
      return CheckValues(motion.channels().values(), "motion.channels.values", motion.frame_count(),
                         channels, channels, " channels",
                         std::max<int64_t>(channels, position_values), limits);
    }
    case v1::SkeletalMotion::kPositions:
      *channel_form = false;
      return CheckValues(motion.positions().values(), "motion.positions.values",
                         motion.frame_count(), 3 * joints, joints, " joints x 3 coordinates",
                         position_values, limits);
    default:
      return absl::InvalidArgumentError("motion.data: neither channels nor positions is set");
  }
}

absl::StatusOr<DistanceOptions> ConvertDistanceOptions(const v1::RetimeSkeletalRequest& request,
                                                       int joints) {
  DistanceOptions options;
  options.root_relative = request.root_relative();
  if (request.joint_weights_size() != 0) {
    if (request.joint_weights_size() != joints) {
      return absl::InvalidArgumentError(
          absl::StrCat("joint_weights: ", request.joint_weights_size(), " weights for ", joints,
                       " joints (give one per joint, or none for all 1)"));
    }
    for (int i = 0; i < joints; ++i) {
      const double w = request.joint_weights(i);
      if (!std::isfinite(w) || w < 0.0) {
        return absl::InvalidArgumentError(
            absl::StrCat("joint_weights[", i, "]: ", w, " must be finite and >= 0"));
      }
    }
    options.weights.assign(request.joint_weights().begin(), request.joint_weights().end());
  }
  if (request.camera_size() != 0) {
    if (request.camera_size() != 16) {
      return absl::InvalidArgumentError(absl::StrCat(
          "camera: ", request.camera_size(), " values, a 4x4 matrix needs 16 (column-major)"));
    }
    std::array<double, 16> matrix;
    for (int i = 0; i < 16; ++i) {
      if (!std::isfinite(request.camera(i))) {
        return absl::InvalidArgumentError(
            absl::StrCat("camera[", i, "]: ", request.camera(i), " is not finite"));
      }
      matrix[i] = request.camera(i);
    }
    options.camera = matrix;
  }
  return options;
}

// The film grid of timing_fps (unset: 24) for the motion's rate; unset when counting in
// source frames. The grid's frame count is checked against the limits as frames are.
absl::Status ConvertGrid(const v1::RetimeSkeletalRequest& request, int64_t work_per_frame,
                         const RequestLimits& limits, SkeletalJob* job) {
  const double timing_fps = request.has_timing_fps() ? request.timing_fps() : kDefaultTimingFps;
  KOMA_RETURN_IF_ERROR(ValidateTimingFps(timing_fps, "timing_fps"));
  switch (request.output_rate()) {
    case v1::OUTPUT_RATE_UNSPECIFIED:
    case v1::SOURCE_RATE:
      break;
    case v1::TIMING_RATE:
      job->output_at_timing_rate = true;
      break;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("output_rate: ", static_cast<int>(request.output_rate()),
                       " is not an OutputRate (1 SOURCE_RATE, 2 TIMING_RATE)"));
  }
  const double source_fps = 1.0 / request.motion().frame_time();
  if (timing_fps > 0) {
    KOMA_RETURN_IF_ERROR(ValidateSourceFps(
        source_fps, absl::StrCat("motion.frame_time: ", request.motion().frame_time(), " s")));
  }
  job->grid = FilmGrid::Make(source_fps, timing_fps);
  if (!job->grid) return absl::OkStatus();
  const int grid_frames = job->grid->GridFrameCount(job->frame_count);
  if (grid_frames < 2) {
    return absl::OutOfRangeError(absl::StrCat(
        "motion: ", job->frame_count, " frames at ", source_fps, " fps (", job->frame_count - 1,
        " x ", request.motion().frame_time(), " s) span less than 2 frames of the ", timing_fps,
        " fps film grid (timing_fps); send a longer clip, or timing_fps: 0 to count "
        "in source frames"));
  }
  return CheckGridValues("motion", grid_frames, timing_fps, work_per_frame, "values per frame",
                         limits);
}

// INVALID_ARGUMENT unless `value` is finite and >= 0 (> 0 with `positive`).
absl::Status CheckRate(double value, absl::string_view field, bool positive) {
  if (std::isfinite(value) && (positive ? value > 0.0 : value >= 0.0)) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(field, ": ", value, " must be finite and ",
                                                 positive ? "> 0" : ">= 0", " (per second)"));
}

// The rates a request asks for: its own, or with none of the paper's counts named, the anime
// defaults for those it leaves unset (docs/semantics.md, "Defaults: anime timing").
struct RequestedRates {
  std::optional<double> omissions_per_second;
  std::optional<double> drawings_per_second;
};

RequestedRates RatesOf(const v1::RetimeSkeletalRequest& request) {
  RequestedRates rates;
  if (request.has_omissions_per_second()) {
    rates.omissions_per_second = request.omissions_per_second();
  }
  if (request.has_drawings_per_second()) rates.drawings_per_second = request.drawings_per_second();
  const bool names_counts =
      request.has_omissions() || request.has_holds() || request.has_max_hold();
  if (!names_counts) {
    if (!rates.omissions_per_second) rates.omissions_per_second = kDefaultOmissionsPerSecond;
    if (!rates.drawings_per_second) rates.drawings_per_second = kDefaultDrawingsPerSecond;
  }
  return rates;
}

// The counts of frame_count counted frames at counted_fps frames per second (the grid's or the
// source's): the request's counts, the paper's defaults for those it leaves unset, or the counts
// its rates (or the anime defaults) give (docs/semantics.md, "Omission rate", "Drawing rate").
absl::StatusOr<RetimeOptions> ConvertRetimeOptions(const v1::RetimeSkeletalRequest& request,
                                                   int frame_count, double counted_fps,
                                                   SkeletalJob* job) {
  RetimeOptions options = DefaultRetimeOptions(frame_count);
  const RequestedRates rates = RatesOf(request);
  if (request.has_omissions_per_second() && request.has_omissions()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "omissions_per_second: ", request.omissions_per_second(), " given with omissions: ",
        request.omissions(), "; give one of the two"));
  }
  if (rates.omissions_per_second) {
    KOMA_RETURN_IF_ERROR(CheckRate(*rates.omissions_per_second, "omissions_per_second", false));
    options.omissions = OmissionsForRate(*rates.omissions_per_second, frame_count, counted_fps);
    job->omissions_per_second = *rates.omissions_per_second;
  }
  if (request.has_omissions()) options.omissions = request.omissions();
  if (request.has_holds()) options.holds = request.holds();
  if (request.has_max_hold()) options.max_hold = request.max_hold();
  if (rates.drawings_per_second) {
    const double rate = *rates.drawings_per_second;
    KOMA_RETURN_IF_ERROR(CheckRate(rate, "drawings_per_second", true));
    job->drawings_per_frame = rate / counted_fps;
    job->drawings_per_second = rate;
    // The hold the rate needs: ceil(fps / rate) counted frames, at least 1, at most the clip.
    if (!request.has_max_hold()) {
      options.max_hold = std::max(1, std::min(CeilOfRate(counted_fps / rate), frame_count));
    }
    options.max_drawings = std::max(1, CeilOfRate(frame_count * job->drawings_per_frame));
    if (!request.has_holds()) {
      job->holds_per_frame_cap = true;
      options.holds = static_cast<int>(
          std::min<int64_t>(int64_t{kHoldStepsPerFrameAndHold} * frame_count * options.max_hold,
                            INT32_MAX));
    }
  }
  if (request.has_keep_length()) options.keep_length = request.keep_length();
  switch (request.order()) {
    case v1::STEP_ORDER_UNSPECIFIED:
    case v1::OMIT_THEN_HOLD:
      options.order = StepOrder::kOmitThenHold;
      break;
    case v1::HOLD_THEN_OMIT:
      options.order = StepOrder::kHoldThenOmit;
      break;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("order: ", static_cast<int>(request.order()),
                       " is not a StepOrder (1 OMIT_THEN_HOLD, 2 HOLD_THEN_OMIT)"));
  }
  KOMA_RETURN_IF_ERROR(ValidateRetimeOptions(options, frame_count));
  return options;
}

}  // namespace

absl::StatusOr<SkeletalJob> ValidateSkeletalRequest(const v1::RetimeSkeletalRequest& request,
                                                    const RequestLimits& limits) {
  if (!request.has_motion()) return absl::InvalidArgumentError("motion: required, not set");
  const v1::SkeletalMotion& motion = request.motion();
  SkeletalJob job;
  KOMA_ASSIGN_OR_RETURN(job.skeleton, ConvertSkeleton(motion.skeleton(), limits));
  KOMA_RETURN_IF_ERROR(CheckTiming(motion));
  job.frame_count = motion.frame_count();
  KOMA_RETURN_IF_ERROR(CheckMotionData(motion, job.skeleton, limits, &job.channel_form));
  const int joints = static_cast<int>(job.skeleton.joints.size());
  KOMA_ASSIGN_OR_RETURN(job.distance_options, ConvertDistanceOptions(request, joints));
  KOMA_RETURN_IF_ERROR(ConvertGrid(request, 3LL * joints, limits, &job));
  if (request.has_cut_neighbour_ratio()) job.cut_rule.neighbour_ratio = request.cut_neighbour_ratio();
  if (request.has_cut_median_ratio()) job.cut_rule.median_ratio = request.cut_median_ratio();
  KOMA_RETURN_IF_ERROR(ValidateCutRule(job.cut_rule));
  if (!job.grid) {
    KOMA_ASSIGN_OR_RETURN(job.retime_options,
                          ConvertRetimeOptions(request, job.frame_count,
                                               1.0 / request.motion().frame_time(), &job));
  } else {
    // Omissions, holds, max_hold and their defaults count grid frames.
    const int grid_frames = job.grid->GridFrameCount(job.frame_count);
    absl::StatusOr<RetimeOptions> options =
        ConvertRetimeOptions(request, grid_frames, job.grid->timing_fps(), &job);
    if (!options.ok()) {
      return absl::Status(
          options.status().code(),
          absl::StrCat(options.status().message(), " (counted on the ", job.grid->timing_fps(),
                       " fps film grid, where the clip has ", grid_frames,
                       " frames; timing_fps: 0 counts in source frames)"));
    }
    job.retime_options = *options;
  }
  job.return_motion = !request.has_return_motion() || request.return_motion();
  if (request.has_given_timing()) {
    const auto& given = request.given_timing().source_frames();
    std::vector<int32_t> frames(given.begin(), given.end());
    const int counted = job.grid ? job.grid->GridFrameCount(job.frame_count) : job.frame_count;
    KOMA_RETURN_IF_ERROR(ValidateGivenSkeletalTiming(frames, job.frame_count, counted,
                                                     "given_timing.source_frames"));
    job.given_source_frames = std::move(frames);
  }
  return job;
}

}  // namespace koma::server

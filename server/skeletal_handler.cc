// Run half of server/skeletal_request.h: validated request -> FK -> RetimeFast -> response.
#include <cstring>
#include <limits>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/forward_kinematics.h"
#include "core/given_skeletal_timing.h"
#include "core/retime_grid.h"
#include "core/retime_shots.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "platform/thread_task_runner.h"
#include "server/file_requests.h"
#include "server/response_slice.h"
#include "server/skeletal_request.h"
#include "server/skeletal_response.h"

namespace koma::server {
namespace {

v1::FrameKind ToProto(FrameKind kind) {
  switch (kind) {
    case FrameKind::kOriginal:
      return v1::ORIGINAL;
    case FrameKind::kDuplicate:
      return v1::DUPLICATE;
    case FrameKind::kHeld:
      return v1::HELD;
  }
  return v1::FRAME_KIND_UNSPECIFIED;
}

absl::Span<const double> SpanOf(const google::protobuf::RepeatedField<double>& field) {
  return absl::MakeConstSpan(field.data(), field.size());
}

int ValuesPerFrame(const SkeletalJob& job) {
  return job.channel_form ? ChannelCount(job.skeleton)
                          : 3 * static_cast<int>(job.skeleton.joints.size());
}

// World positions computed by FK (channel form) into `storage`, or a view of the request's
// own positions (no copy).
absl::StatusOr<absl::Span<const double>> WorldPositions(const v1::SkeletalMotion& motion,
                                                        const SkeletalJob& job, int threads,
                                                        LargeArray<double>& storage) {
  if (!job.channel_form) return SpanOf(motion.positions().values());
  // Room for the response as well (at most the request's values plus ~20 bytes a frame for the
  // timing fields): freed before the response is encoded, these positions' memory is then
  // exactly what UninitialisedSlice takes back from the huge-page cache (server/response_slice.h).
  const size_t response_doubles = static_cast<size_t>(motion.channels().values_size()) +
                                  3 * static_cast<size_t>(job.frame_count) + 8192;
  absl::StatusOr<LargeArray<double>> positions =
      ComputeWorldPositions(job.skeleton, SpanOf(motion.channels().values()), job.frame_count,
                            platform::ThreadTaskRunner(threads), response_doubles);
  if (!positions.ok()) return positions.status();
  storage = *std::move(positions);
  return absl::MakeConstSpan(storage);
}

// Output frame t is a verbatim copy of source frame map.source_frames[t]. The space is taken
// uninitialised (Reserve + AddNAlreadyReserved) and written once: Resize would first zero all
// of it, a second pass over as many bytes as the request (~77 MB at 100k frames x 96 channels).
void CopyFrames(const google::protobuf::RepeatedField<double>& source, int per_frame,
                const TimingMap& map, google::protobuf::RepeatedField<double>* out) {
  const int total = static_cast<int>(map.source_frames.size()) * per_frame;
  out->Clear();
  if (total == 0) return;
  out->Reserve(total);
  double* dst = out->AddNAlreadyReserved(total);
  for (int32_t frame : map.source_frames) {
    std::memcpy(dst, source.data() + static_cast<size_t>(frame) * per_frame,
                sizeof(double) * per_frame);
    dst += per_frame;
  }
}

// Seconds per frame of the returned motion: the source's, or the grid's at TIMING_RATE.
double OutputFrameTime(const v1::SkeletalMotion& in, const SkeletalJob& job) {
  if (job.grid && job.output_at_timing_rate) return 1.0 / job.grid->timing_fps();
  return in.frame_time();
}

void FillMotion(const v1::SkeletalMotion& in, const SkeletalJob& job, const TimingMap& map,
                v1::SkeletalMotion* out) {
  *out->mutable_skeleton() = in.skeleton();
  out->set_frame_time(OutputFrameTime(in, job));
  out->set_frame_count(static_cast<int32_t>(map.source_frames.size()));
  const int per_frame = ValuesPerFrame(job);
  if (job.channel_form) {
    CopyFrames(in.channels().values(), per_frame, map, out->mutable_channels()->mutable_values());
  } else {
    CopyFrames(in.positions().values(), per_frame, map, out->mutable_positions()->mutable_values());
  }
}

// Every response field but the motion.
void FillHead(const SkeletalJob& job, const TimingMap& map, const std::vector<double>& input_ssd,
              v1::RetimeSkeletalResponse* response) {
  response->mutable_source_frames()->Add(map.source_frames.begin(), map.source_frames.end());
  response->mutable_kinds()->Reserve(static_cast<int>(map.kinds.size()));
  for (FrameKind kind : map.kinds) response->add_kinds(ToProto(kind));
  response->mutable_deleted_frames()->Add(map.deleted.begin(), map.deleted.end());
  response->mutable_hidden_frames()->Add(map.hidden.begin(), map.hidden.end());
  response->mutable_input_ssd()->Add(input_ssd.begin(), input_ssd.end());
  response->set_omissions_applied(map.omissions_applied);
  response->set_duplicates_applied(map.duplicates_applied);
  response->set_duplicates_skipped(map.duplicates_skipped);
  response->set_holds_applied(map.holds_applied);
  response->set_omissions_requested(job.retime_options.omissions);
  response->set_holds_requested(job.retime_options.holds);
  response->set_max_hold(job.retime_options.max_hold);
}

struct Retimed {
  SkeletalJob job;
  TimingMap map;
  std::vector<double> input_ssd;      // per grid frame with a grid, else per source frame
  std::vector<int32_t> grid_frames;   // with a grid: per output frame, its grid frame
  std::vector<int32_t> grid_samples;  // with a grid: per grid frame, its source frame
  std::vector<int32_t> cuts;          // the first source frame of each shot after a cut
};

// The response fields after the motion (14 and up): the cuts (20), what became of the
// duplicates (50, 51), the rates used (52, 53), and the film grid's, empty without one.
void FillTailFields(const Retimed& retimed, v1::RetimeSkeletalResponse* response) {
  response->mutable_cut_frames()->Add(retimed.cuts.begin(), retimed.cuts.end());
  response->set_duplicates_omitted(retimed.map.duplicates_omitted);
  response->set_duplicates_held(retimed.map.duplicates_held);
  response->set_omissions_per_second(retimed.job.omissions_per_second);
  response->set_drawings_per_second(retimed.job.drawings_per_second);
  response->set_timing_given(retimed.job.given_source_frames.has_value());
  if (!retimed.job.grid) return;
  response->set_timing_fps(retimed.job.grid->timing_fps());
  response->mutable_grid_frames()->Add(retimed.grid_frames.begin(), retimed.grid_frames.end());
  response->mutable_grid_source_frames()->Add(retimed.grid_samples.begin(),
                                              retimed.grid_samples.end());
}

// Positions of the grid's frames: frame g is a copy of source frame samples[g].
std::vector<double> GridPositions(absl::Span<const double> positions,
                                  const std::vector<int32_t>& samples, int per_frame) {
  std::vector<double> out(samples.size() * static_cast<size_t>(per_frame));
  double* dst = out.data();
  for (int32_t frame : samples) {
    std::memcpy(dst, positions.data() + static_cast<size_t>(frame) * per_frame,
                sizeof(double) * per_frame);
    dst += per_frame;
  }
  return out;
}

// RetimeFast on the grid's samples of `positions`, its timing map expanded back to output
// frames (film grid: docs/semantics.md).
absl::StatusOr<FrameDistance> GridDistance(absl::Span<const double> positions, Retimed& out,
                                           std::vector<double>& grid_positions) {
  const SkeletalJob& job = out.job;
  const int joints = static_cast<int>(job.skeleton.joints.size());
  out.grid_samples = GridSamples(*job.grid, job.frame_count);
  grid_positions = GridPositions(positions, out.grid_samples, 3 * joints);
  return FrameDistance::CreateView(grid_positions, static_cast<int>(out.grid_samples.size()),
                                   joints, job.distance_options);
}

// A clip with cuts: each shot retimed as if it were alone, with its share of the counts
// (docs/semantics.md, "Cuts and shots").
absl::Status RetimeByShots(absl::Span<const double> positions, Retimed& out) {
  const SkeletalJob& job = out.job;
  std::vector<int32_t> starts{0};
  starts.insert(starts.end(), out.cuts.begin(), out.cuts.end());
  std::vector<int> lengths;  // counted frames per shot
  for (size_t i = 0; i < starts.size(); ++i) {
    const int n = (i + 1 < starts.size() ? starts[i + 1] : job.frame_count) - starts[i];
    lengths.push_back(job.grid ? job.grid->GridFrameCount(n) : n);
  }
  ShotBudget budget;
  budget.totals = job.retime_options;
  budget.drawings_per_frame = job.drawings_per_frame;
  budget.holds_per_frame_cap = job.holds_per_frame_cap;
  absl::StatusOr<ShotsRetimed> shots =
      RetimeShots(positions, job.frame_count, static_cast<int>(job.skeleton.joints.size()),
                  job.distance_options, job.grid, !job.output_at_timing_rate, starts,
                  ShotOptions(budget, lengths));
  if (!shots.ok()) {
    return absl::Status(shots.status().code(), absl::StrCat("motion: ", shots.status().message()));
  }
  out.map = std::move(shots->map);
  out.input_ssd = std::move(shots->input_ssd);
  out.grid_frames = std::move(shots->grid_frames);
  out.grid_samples = std::move(shots->grid_samples);
  return absl::OkStatus();
}

// A distance step's failure (the inputs are finite by now; what fails is their size after FK or
// the transforms), named as the motion's.
template <typename T>
absl::StatusOr<T> InMotion(absl::StatusOr<T> result) {
  if (result.ok()) return result;
  return absl::Status(result.status().code(), absl::StrCat("motion: ", result.status().message()));
}

// A given timing (docs/semantics.md, "A given timing"): expanded as a chosen one, nothing
// measured, so no forward kinematics either. The counts the response reports: 0, and max_hold
// the longest given hold.
void ApplyGiven(Retimed& out) {
  SkeletalJob& job = out.job;
  GivenSkeletalRetimed given = ApplyGivenSkeletalTiming(*job.given_source_frames, job.grid,
                                                        job.frame_count,
                                                        !job.output_at_timing_rate);
  out.map = std::move(given.map);
  out.grid_frames = std::move(given.grid_frames);
  out.grid_samples = std::move(given.grid_samples);
  job.retime_options.omissions = 0;
  job.retime_options.holds = 0;
  job.retime_options.max_hold = given.longest_hold;
  job.omissions_per_second = 0.0;
  job.drawings_per_second = 0.0;
}

// Validates, runs forward kinematics (channel form) and RetimeFast.
absl::StatusOr<Retimed> Retime(const v1::RetimeSkeletalRequest& request,
                               const RequestLimits& limits) {
  Retimed out;
  KOMA_ASSIGN_OR_RETURN(out.job, ValidateSkeletalRequest(request, limits));
  if (out.job.given_source_frames) {
    ApplyGiven(out);
    return out;
  }
  const SkeletalJob& job = out.job;
  // In this function FK's world positions (as large as the request) are alive; they are freed
  // before the response is built, so a large call never holds request, positions and
  // response at once (peak memory: measured in docs/benchmarks.md).
  LargeArray<double> computed_positions;
  KOMA_ASSIGN_OR_RETURN(
      const absl::Span<const double> positions,
      WorldPositions(request.motion(), job, limits.threads_per_call, computed_positions));
  const int joints = static_cast<int>(job.skeleton.joints.size());
  const bool find_cuts = job.cut_rule.neighbour_ratio != 0.0;
  if (!job.grid) {
    // Counted in source frames: one distance over the source serves the cut search and, when
    // there is no cut, the retiming, which takes the SSD the search measured (the same bits
    // RetimeFast would compute) instead of measuring it again.
    // With cuts the distance (a copy, with a transform) is freed before the shots make theirs.
    {
      KOMA_ASSIGN_OR_RETURN(const FrameDistance distance,
                            InMotion(FrameDistance::CreateView(positions, job.frame_count, joints,
                                                               job.distance_options)));
      if (!find_cuts) {
        out.map = RetimeFast(distance, job.retime_options, &out.input_ssd);
        return out;
      }
      std::vector<double> source_ssd = RetimeInputSsd(distance);
      out.cuts = FindCuts(source_ssd, job.cut_rule);
      if (out.cuts.empty()) {
        out.map = RetimeFastWithInputSsd(distance, job.retime_options, std::move(source_ssd),
                                         &out.input_ssd);
        return out;
      }
    }
    KOMA_RETURN_IF_ERROR(RetimeByShots(positions, out));
    return out;
  }
  if (find_cuts) {
    // On a film grid the cut search reads the source frames, the retiming the grid's.
    KOMA_ASSIGN_OR_RETURN(
        const std::vector<double> source_ssd,
        InMotion(SourceSsd(positions, job.frame_count, joints, job.distance_options)));
    out.cuts = FindCuts(source_ssd, job.cut_rule);
  }
  if (!out.cuts.empty()) {
    KOMA_RETURN_IF_ERROR(RetimeByShots(positions, out));
    return out;
  }
  std::vector<double> grid_positions;
  KOMA_ASSIGN_OR_RETURN(const FrameDistance distance,
                        InMotion(GridDistance(positions, out, grid_positions)));
  out.map = RetimeFast(distance, job.retime_options, &out.input_ssd);
  GridRetimed expanded = ExpandGridTiming(out.map, out.grid_samples, *job.grid, job.frame_count,
                                          !job.output_at_timing_rate);
  out.map = std::move(expanded.map);
  out.grid_frames = std::move(expanded.grid_frames);
  return out;
}

}  // namespace

absl::Status RetimeSkeletalAnswer(const v1::RetimeSkeletalRequest& request,
                                  const RequestLimits& limits, SkeletalAnswer* answer) {
  if (CarriesFile(request)) return RetimeSkeletalFileAnswer(request, limits, answer);
  KOMA_ASSIGN_OR_RETURN(const Retimed retimed, Retime(request, limits));
  KOMA_RETURN_IF_ERROR(StopReason());  // stopped: the map is unfinished (core/stop_check.h)
  v1::RetimeSkeletalResponse head;
  FillHead(retimed.job, retimed.map, retimed.input_ssd, &head);
  v1::RetimeSkeletalResponse tail;
  FillTailFields(retimed, &tail);
  const SkeletalResponseEncoder encoder(head, tail, retimed.job.return_motion, request.motion(),
                                        OutputFrameTime(request.motion(), retimed.job),
                                        retimed.job.channel_form, ValuesPerFrame(retimed.job),
                                        retimed.map.source_frames);
  const size_t size = encoder.size();
  if (size > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "response: ", size, " bytes is over protobuf's 2 GiB message limit; send fewer frames"));
  }
  answer->bytes = UninitialisedSlice(size);
  encoder.WriteTo(const_cast<uint8_t*>(answer->bytes.begin()));
  return absl::OkStatus();
}

absl::Status HandleRetimeSkeletal(const v1::RetimeSkeletalRequest& request,
                                  const RequestLimits& limits,
                                  v1::RetimeSkeletalResponse* response) {
  if (CarriesFile(request)) return HandleRetimeSkeletalFile(request, limits, response);
  KOMA_ASSIGN_OR_RETURN(const Retimed retimed, Retime(request, limits));
  KOMA_RETURN_IF_ERROR(StopReason());  // stopped: the map is unfinished (core/stop_check.h)
  FillHead(retimed.job, retimed.map, retimed.input_ssd, response);
  if (retimed.job.return_motion) {
    FillMotion(request.motion(), retimed.job, retimed.map, response->mutable_motion());
  }
  FillTailFields(retimed, response);
  return absl::OkStatus();
}

}  // namespace koma::server

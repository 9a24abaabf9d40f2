#include "client/skeletal_command.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/channel.h"
#include "client/files.h"
#include "client/report/skeletal_report.h"
#include "client/skeletal_convert.h"
#include "formats/bvh.h"
#include "formats/timing_sheet.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

v1::RetimeSkeletalRequest MakeRequest(const SkeletalArgs& args, const SkeletalClip& clip) {
  v1::RetimeSkeletalRequest request;
  *request.mutable_motion() = ToProto(clip);
  if (args.omissions) request.set_omissions(*args.omissions);
  if (args.holds) request.set_holds(*args.holds);
  if (args.max_hold) request.set_max_hold(*args.max_hold);
  request.set_keep_length(args.keep_length);
  request.set_order(args.hold_first ? v1::HOLD_THEN_OMIT : v1::OMIT_THEN_HOLD);
  request.set_root_relative(args.root_relative);
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  if (args.output_at_timing_rate) request.set_output_rate(v1::TIMING_RATE);
  return request;
}

// "3-5, 9, 12-13": ascending integers as compact ranges; "none" when empty.
std::string Ranges(const std::vector<int>& sorted) {
  if (sorted.empty()) return "none";
  std::vector<std::string> parts;
  size_t i = 0;
  while (i < sorted.size()) {
    size_t j = i;
    while (j + 1 < sorted.size() && sorted[j + 1] == sorted[j] + 1) ++j;
    parts.push_back(i == j ? absl::StrCat(sorted[i]) : absl::StrCat(sorted[i], "-", sorted[j]));
    i = j + 1;
  }
  return absl::StrJoin(parts, ", ");
}

std::vector<int> OutputFramesOfKind(const v1::RetimeSkeletalResponse& response,
                                    v1::FrameKind kind) {
  std::vector<int> frames;
  for (int t = 0; t < response.kinds_size(); ++t) {
    if (response.kinds(t) == kind) frames.push_back(t);
  }
  return frames;
}

// Lengths of the runs of one drawing (one source frame) in output frames, in order.
std::vector<int> RunLengths(const v1::RetimeSkeletalResponse& response) {
  std::vector<int> runs;
  for (int t = 0; t < response.source_frames_size(); ++t) {
    if (t > 0 && response.source_frames(t) == response.source_frames(t - 1)) {
      ++runs.back();
    } else {
      runs.push_back(1);
    }
  }
  return runs;
}

// "on the 24 fps film grid: 105 grid frames; drawings shown 42-125 ms (median 83 ms), the
// source showed each frame 8.3 ms": what the grid did, in the units a viewer sees.
void PrintGridSummary(const SkeletalClip& clip, const v1::RetimeSkeletalResponse& response) {
  if (response.timing_fps() <= 0) return;
  std::vector<int> runs = RunLengths(response);
  const double frame_ms = 1000.0 * response.motion().frame_time();
  const double out_ms = frame_ms > 0 ? frame_ms : 1000.0 * clip.frame_time;
  std::sort(runs.begin(), runs.end());
  std::printf(
      "  film grid  %.4g fps: %d grid frames; %zu drawings shown %.0f-%.0f ms (median "
      "%.0f ms); the source showed each frame %.3g ms\n",
      response.timing_fps(), response.grid_source_frames_size(), runs.size(), runs.front() * out_ms,
      runs.back() * out_ms, runs[runs.size() / 2] * out_ms, 1000.0 * clip.frame_time);
}

int LongestRun(const v1::RetimeSkeletalResponse& response) {
  int longest = 0;
  int run = 0;
  for (int t = 0; t < response.source_frames_size(); ++t) {
    run = (t > 0 && response.source_frames(t) == response.source_frames(t - 1)) ? run + 1 : 1;
    longest = std::max(longest, run);
  }
  return longest;
}

void PrintSummary(const SkeletalArgs& args, const SkeletalClip& clip,
                  const v1::RetimeSkeletalResponse& response) {
  const std::vector<int> deleted(response.deleted_frames().begin(),
                                 response.deleted_frames().end());
  const std::vector<int> hidden(response.hidden_frames().begin(), response.hidden_frames().end());
  std::printf("%s: %d frames, %zu joints, %.4g fps -> %s (%d frames)\n", args.input.c_str(),
              clip.frame_count, clip.skeleton.joints.size(), 1.0 / clip.frame_time,
              args.output.c_str(), response.source_frames_size());
  std::printf("  omitted    %3d inbetweens; source frames gone: %s\n", response.omissions_applied(),
              Ranges(deleted).c_str());
  std::printf("  duplicated %3d frames to keep the length%s; DUPLICATE at output frames %s\n",
              response.duplicates_applied(),
              response.duplicates_skipped() > 0
                  ? absl::StrCat(" (", response.duplicates_skipped(), " skipped)").c_str()
                  : "",
              Ranges(OutputFramesOfKind(response, v1::DUPLICATE)).c_str());
  std::printf("  held       %3d hold steps; HELD at output frames %s\n", response.holds_applied(),
              Ranges(OutputFramesOfKind(response, v1::HELD)).c_str());
  std::printf("                 source frames hidden by holds: %s\n", Ranges(hidden).c_str());
  std::printf("  longest hold %d frames; requested omissions %d, holds %d, max_hold %d%s\n",
              LongestRun(response), response.omissions_requested(), response.holds_requested(),
              response.max_hold(), response.timing_fps() > 0 ? " (grid frames)" : "");
  PrintGridSummary(clip, response);
  if (!args.timing.empty()) std::printf("  timing sheet: %s\n", args.timing.c_str());
}

}  // namespace

int RunSkeletal(const SkeletalArgs& args) {
  absl::StatusOr<std::string> text = ReadFile(args.input);
  if (!text.ok()) return ReportError(text.status());
  absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(*text);
  if (!clip.ok()) {
    return ReportError(
        absl::InvalidArgumentError(absl::StrCat(args.input, ": ", clip.status().message())));
  }
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report}); !s.ok()) {
    return ReportError(s);
  }
  absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> stub = NewRetimeStub(args.server);
  if (!stub.ok()) return ReportError(stub.status());
  grpc::ClientContext context;
  SetDeadline(&context, args.deadline_seconds);
  v1::RetimeSkeletalResponse response;
  const v1::RetimeSkeletalRequest request = MakeRequest(args, *clip);
  const grpc::Status status = (*stub)->RetimeSkeletal(&context, request, &response);
  if (!status.ok()) return ReportRpcError(status);

  absl::StatusOr<SkeletalClip> retimed = ClipFromResponse(response, clip->skeleton);
  if (!retimed.ok()) return ReportError(retimed.status());
  if (absl::Status s = WriteFile(args.output, formats::WriteBvh(*retimed)); !s.ok()) {
    return ReportError(s);
  }
  if (!args.timing.empty()) {
    const std::vector<int32_t> grid_frames(response.grid_frames().begin(),
                                           response.grid_frames().end());
    const double frame_time =
        response.has_motion() ? response.motion().frame_time() : clip->frame_time;
    const std::string sheet =
        formats::WriteTimingSheetCsv(TimingMapFromResponse(response), frame_time,
                                     response.timing_fps() > 0 ? &grid_frames : nullptr);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return ReportError(s);
  }
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteSkeletalReport(args.report, request, response, args.input);
        !s.ok()) {
      return ReportError(s);
    }
  }
  PrintSummary(args, *clip, response);
  if (!args.report.empty()) std::printf("  report: %s\n", args.report.c_str());
  return 0;
}

}  // namespace koma::client

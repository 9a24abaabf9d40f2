#include "client/lip_blink_command.h"

#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/channel.h"
#include "client/curve_files.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/report/lip_blink_report.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

constexpr int kUsageError = 2;

v1::LipBlinkRequest MakeRequest(const LipBlinkArgs& args, const CurveSet& curves) {
  v1::LipBlinkRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  v1::MouthSettings* mouth = request.mutable_mouth();
  for (const std::string& id : args.mouth_ids) mouth->add_ids(id);
  mouth->set_mode(args.mode == "follow" ? v1::MOUTH_FOLLOW : v1::MOUTH_RANDOM);
  if (args.frames_per_shape) mouth->set_frames_per_shape(*args.frames_per_shape);
  v1::EyeSettings* eyes = request.mutable_eyes();
  for (const std::string& id : args.eye_ids) eyes->add_ids(id);
  if (args.unlinked_eyes) eyes->set_linked(false);
  if (args.auto_blink_mean_s) {
    eyes->mutable_auto_blink()->set_enabled(true);
    eyes->mutable_auto_blink()->set_mean_interval_s(*args.auto_blink_mean_s);
  }
  if (args.seed) request.set_seed(*args.seed);
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  return request;
}

const char* ShapeName(int shape) {
  switch (shape) {
    case v1::MOUTH_CLOSED:
      return "closed";
    case v1::MOUTH_MID:
      return "mid";
    case v1::MOUTH_OPEN:
      return "open";
    default:
      return "?";
  }
}

// Frame numbers of the response: the curves' frames, or film-grid frames (timing_fps > 0),
// which the summary also gives in seconds.
struct Frames {
  double grid_fps = 0;
  const char* noun() const { return grid_fps > 0 ? "grid frames" : "frames"; }
  const char* one() const { return grid_fps > 0 ? "grid frame" : "frame"; }
  std::string Range(int first, int last) const {
    std::string text = absl::StrCat(first, "-", last);
    if (grid_fps > 0) {
      absl::StrAppend(&text,
                      absl::StrFormat(" (%.2f-%.2f s)", first / grid_fps, (last + 1) / grid_fps));
    }
    return text;
  }
  std::string At(int frame) const {
    return grid_fps > 0 ? absl::StrFormat("%d (%.2f s)", frame, frame / grid_fps)
                        : absl::StrCat(frame);
  }
};

void PrintMouth(const v1::MouthTrack& mouth, const Frames& frames) {
  std::vector<std::string> speech;
  for (const v1::FrameInterval& i : mouth.speech()) {
    speech.push_back(frames.Range(i.begin(), i.end() - 1));
  }
  std::vector<std::string> shapes;
  for (const v1::MouthHold& hold : mouth.holds()) shapes.push_back(ShapeName(hold.shape()));
  std::printf("  mouth %s: speech at %s %s; %d holds: %s\n", mouth.id().c_str(), frames.noun(),
              speech.empty() ? "none" : absl::StrJoin(speech, ", ").c_str(), mouth.holds_size(),
              absl::StrJoin(shapes, " ").c_str());
}

void PrintEye(const v1::EyeTrack& eye, const Frames& frames) {
  std::vector<std::string> blinks;
  for (const v1::Blink& b : eye.blinks()) {
    blinks.push_back(absl::StrCat(frames.one(), " ", frames.At(b.closed_begin()), " (hold ",
                                  b.hold(), b.automatic() ? ", auto)" : ")"));
  }
  std::printf("  eye %s: %d blinks%s%s\n", eye.id().c_str(), eye.blinks_size(),
              blinks.empty() ? "" : ": ", absl::StrJoin(blinks, ", ").c_str());
}

absl::Status WriteOutput(const LipBlinkArgs& args, const CurveInput& input,
                         const v1::LipBlinkResponse& response) {
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < input.curves.curves.size(); ++i) index_of[input.curves.curves[i].id] = i;
  std::vector<std::optional<CurveReplacement>> replacements(input.curves.curves.size());
  for (const v1::ConvertedCurve& curve : response.curves()) {
    replacements[index_of.at(curve.id())] =
        CurveReplacement{std::vector<double>(curve.values().begin(), curve.values().end()),
                         StepsFromProto(curve.stepped())};
  }
  return WriteCurveOutput(args.output, input, replacements);
}

}  // namespace

int RunLipBlink(const LipBlinkArgs& args) {
  if (!CanWriteOutput(args.input, args.output)) return kUsageError;
  absl::StatusOr<CurveInput> input = ReadCurveInput(args.input, args.csv_fps);
  if (!input.ok()) return ReportError(input.status());
  if (absl::Status s = CheckWritable({args.output, args.report}); !s.ok()) return ReportError(s);

  absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> stub = NewRetimeStub(args.server);
  if (!stub.ok()) return ReportError(stub.status());
  grpc::ClientContext context;
  SetDeadline(&context, args.deadline_seconds);
  v1::LipBlinkResponse response;
  const v1::LipBlinkRequest request = MakeRequest(args, input->curves);
  const grpc::Status status = (*stub)->LipBlink(&context, request, &response);
  if (!status.ok()) return ReportRpcError(status);
  if (absl::Status s = WriteOutput(args, *input, response); !s.ok()) return ReportError(s);

  std::printf("%s: %d frames at %.4g fps -> %s (seed %llu, %s mouth)\n", args.input.c_str(),
              input->curves.frame_count, input->curves.fps, args.output.c_str(),
              static_cast<unsigned long long>(response.seed()), args.mode.c_str());
  const Frames frames{response.timing_fps()};
  if (frames.grid_fps > 0) {
    std::printf(
        "  on the %.4g fps film grid: holds and frames below are its frames (%.1f ms "
        "each)\n",
        frames.grid_fps, 1000.0 / frames.grid_fps);
  }
  for (const v1::MouthTrack& mouth : response.mouths()) PrintMouth(mouth, frames);
  for (const v1::EyeTrack& eye : response.eyes()) PrintEye(eye, frames);
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteLipBlinkReport(args.report, request, response, args.input);
        !s.ok()) {
      return ReportError(s);
    }
    std::printf("  report: %s\n", args.report.c_str());
  }
  return 0;
}

}  // namespace koma::client

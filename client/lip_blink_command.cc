#include "client/lip_blink_command.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/lip_blink_summary.h"
#include "client/report/lip_blink_report.h"
#include "client/retime_call.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

void AddIntervals(const std::vector<FlagInterval>& intervals,
                  google::protobuf::RepeatedPtrField<v1::FrameInterval>* out) {
  for (const FlagInterval& i : intervals) {
    v1::FrameInterval* f = out->Add();
    f->set_begin(i.begin);
    f->set_end(i.end);
  }
}

}  // namespace

v1::LipBlinkRequest BuildLipBlinkRequest(const LipBlinkArgs& args, const CurveSet& curves) {
  v1::LipBlinkRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  v1::MouthSettings* mouth = request.mutable_mouth();
  for (const std::string& id : args.mouth_ids) mouth->add_ids(id);
  mouth->set_mode(args.mode == "follow" ? v1::MOUTH_FOLLOW : v1::MOUTH_RANDOM);
  if (args.frames_per_shape) mouth->set_frames_per_shape(*args.frames_per_shape);
  if (args.mouth_mid_ratio) mouth->set_mid_ratio(*args.mouth_mid_ratio);
  if (args.mouth_min) mouth->set_min(*args.mouth_min);
  if (args.mouth_max) mouth->set_max(*args.mouth_max);
  AddIntervals(args.speech, mouth->mutable_speech());

  v1::EyeSettings* eyes = request.mutable_eyes();
  for (const std::string& id : args.eye_ids) eyes->add_ids(id);
  if (args.eyes_mid_ratio) eyes->set_mid_ratio(*args.eyes_mid_ratio);
  if (args.eyes_threshold) eyes->set_threshold(*args.eyes_threshold);
  if (args.eyes_min) eyes->set_min(*args.eyes_min);
  if (args.eyes_max) eyes->set_max(*args.eyes_max);
  if (args.eyes_linked) {
    eyes->set_linked(*args.eyes_linked);
  } else if (args.unlinked_eyes) {
    eyes->set_linked(false);
  }
  const bool any_auto_blink = args.auto_blink_mean_s || args.auto_blink_spread_s ||
                              args.auto_blink_hold || !args.auto_blink_keep.empty();
  if (args.auto_blink_enabled.value_or(any_auto_blink)) {
    v1::AutoBlink* blink = eyes->mutable_auto_blink();
    blink->set_enabled(true);
    if (args.auto_blink_mean_s) blink->set_mean_interval_s(*args.auto_blink_mean_s);
    if (args.auto_blink_spread_s) blink->set_spread_s(*args.auto_blink_spread_s);
    if (args.auto_blink_hold) blink->set_hold(*args.auto_blink_hold);
    AddIntervals(args.auto_blink_keep, blink->mutable_keep());
  }
  if (args.seed) request.set_seed(*args.seed);
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  return request;
}

v1::LipBlinkRequest BuildLipBlinkFileRequest(const LipBlinkArgs& args, const CurveInput& input) {
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, input.curves);
  if (args.send_file) PutCurveFile(args, input, &request);
  return request;
}

absl::Status CheckLipBlinkFlags(const LipBlinkArgs& args) {
  if (args.output.empty()) {
    return absl::InvalidArgumentError("-o/--output OUT.motion3.json or OUT.csv is required");
  }
  return CheckOneOnStdout(
      {{"-o", args.output}, {"--report", args.report}, {"--xdts", args.xdts}}, args.json);
}

absl::Status WriteLipBlinkOutputs(const LipBlinkArgs& args, const CurveInput& input,
                                  const v1::LipBlinkResponse& response) {
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < input.curves.curves.size(); ++i) index_of[input.curves.curves[i].id] = i;
  std::vector<std::optional<CurveReplacement>> replacements(input.curves.curves.size());
  for (const v1::ConvertedCurve& curve : response.curves()) {
    const auto it = index_of.find(curve.id());
    if (it == index_of.end()) {
      return absl::InternalError(
          absl::StrCat("the server answered a curve \"", curve.id(), "\" the input does not have"));
    }
    replacements[it->second] = convert::ReplacementFromProto(curve);
  }
  if (absl::Status s =
          WriteCurveOutput(args.output, input, replacements, CurveFormatFromFlag(args.format));
      !s.ok()) {
    return s;
  }
  if (!args.xdts.empty()) {
    absl::StatusOr<formats::XdtsSheet> sheet =
        LipBlinkXdtsSheet(response, input.curves.fps, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return sheet.status();
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) return s;
  }
  return absl::OkStatus();
}

int RunLipBlink(const LipBlinkArgs& args) {
  const CommandOutput out("lipblink", args.json, args.quiet, args.server);
  if (absl::Status s = CheckLipBlinkFlags(args); !s.ok()) return out.UsageFailure(s);
  absl::StatusOr<CurveInput> input =
      ReadCurveInput(args.input, args.csv_fps, CurveFormat::kAuto, "lipblink");
  if (!input.ok()) return out.Failure(input.status());
  absl::StatusOr<CurveFormat> format =
      CurveOutputFormat(args.output, CurveFormatFromFlag(args.format), *input);
  if (!format.ok()) return out.UsageFailure(format.status());
  if (absl::Status s = CheckWritable({args.output, args.report, args.xdts}); !s.ok()) return out.Failure(s);

  const v1::LipBlinkRequest request = BuildLipBlinkRequest(args, input->curves);
  // --send-file: the wire carries the file; the report still reads the decoded request.
  std::optional<v1::LipBlinkRequest> file_request;
  if (args.send_file) file_request = BuildLipBlinkFileRequest(args, *input);
  v1::LipBlinkResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink,
                            file_request ? *file_request : request, &response);
      code >= 0) {
    return code;
  }
  if (absl::Status s = WriteLipBlinkOutputs(args, *input, response); !s.ok()) {
    return out.Failure(s);
  }
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteLipBlinkReport(args.report, request, response, args.input);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(LipBlinkSummaryText(args, input->curves, response) + XdtsLine(args.xdts) +
                  ReportLine(args.report),
              LipBlinkSummaryJson(args, input->curves, response),
              IsStdio(args.output) || IsStdio(args.report) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

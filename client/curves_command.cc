#include "client/curves_command.h"

#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "client/curves_convert.h"
#include "client/curves_summary.h"
#include "client/files.h"
#include "client/flag_values.h"
#include "client/report/curves_report.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"
#include "client/retime_call.h"
#include "formats/drawing_sheet.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

// "ParamHair=2" -> request.curve_overrides.
absl::Status AddCurveOverrides(const std::vector<std::string>& entries,
                               v1::RetimeCurvesRequest& request) {
  for (const std::string& entry : entries) {
    const size_t equals = entry.rfind('=');
    if (equals == std::string::npos || equals == 0) {
      return absl::InvalidArgumentError(
          absl::StrCat("--curve-on: \"", entry, "\" is not ID=N, e.g. ParamHair=2"));
    }
    absl::StatusOr<int64_t> n =
        ParseWholeNumber("--curve-on", entry.substr(equals + 1), 1, INT32_MAX);
    if (!n.ok()) return n.status();
    v1::CurveOverride* o = request.add_curve_overrides();
    o->set_curve_id(entry.substr(0, equals));
    o->set_frames_per_drawing(static_cast<int>(*n));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<SegmentOverrideFlag> ParseSegmentOverride(const std::string& text) {
  constexpr char kFlag[] = "--segment-overrides";
  const std::string usage = absl::StrCat(
      kFlag, ": \"", text,
      "\" is not SEG:KEY=VALUE,... with KEY on (frames per drawing), tame or tsume, e.g. "
      "1:on=2,tame=1.5");
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return absl::InvalidArgumentError(usage);
  SegmentOverrideFlag out;
  absl::StatusOr<int64_t> segment = ParseWholeNumber(kFlag, text.substr(0, colon), 0);
  if (!segment.ok()) return segment.status();
  out.segment = static_cast<int>(*segment);
  const std::string rest = text.substr(colon + 1);
  if (rest.empty()) return absl::InvalidArgumentError(usage);
  for (absl::string_view setting : absl::StrSplit(rest, ',')) {
    const std::vector<std::string> kv = absl::StrSplit(setting, absl::MaxSplits('=', 1));
    if (kv.size() != 2) return absl::InvalidArgumentError(usage);
    const std::string& key = kv[0];
    const std::string flag = absl::StrCat(kFlag, " ", key);
    if (key == "on" || key == "frames-per-drawing" || key == "frames_per_drawing") {
      absl::StatusOr<int64_t> n = ParseWholeNumber(flag, kv[1], 1);
      if (!n.ok()) return n.status();
      out.frames_per_drawing = static_cast<int>(*n);
    } else if (key == "tame" || key == "tsume") {
      absl::StatusOr<double> s = ParseNumber(flag, kv[1], AtLeast(1));
      if (!s.ok()) return s.status();
      (key == "tame" ? out.tame : out.tsume) = *s;
    } else {
      return absl::InvalidArgumentError(usage);
    }
  }
  return out;
}

absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesRequest(const CurvesArgs& args,
                                                           const CurveSet& curves) {
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  request.mutable_key_frames()->Add(args.keys.begin(), args.keys.end());
  if (args.frames_per_drawing) request.set_frames_per_drawing(*args.frames_per_drawing);
  if (args.tame) request.set_tame(*args.tame);
  if (args.tsume) request.set_tsume(*args.tsume);
  if (absl::Status s = AddCurveOverrides(args.curve_on, request); !s.ok()) return s;
  for (const SegmentOverrideFlag& flag : args.segment_overrides) {
    v1::SegmentOverride* o = request.add_segment_overrides();
    o->set_segment(flag.segment);
    if (flag.frames_per_drawing) o->set_frames_per_drawing(*flag.frames_per_drawing);
    if (flag.tame) o->set_tame(*flag.tame);
    if (flag.tsume) o->set_tsume(*flag.tsume);
  }
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  return request;
}

absl::StatusOr<v1::RetimeCurvesRequest> BuildCurvesFileRequest(const CurvesArgs& args,
                                                               const CurveInput& input) {
  absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args, input.curves);
  if (request.ok() && args.send_file) PutCurveFile(args, input, &*request);
  return request;
}

absl::Status CheckCurvesFlags(const CurvesArgs& args) {
  if (args.timing_only && args.timing.empty() && args.xdts.empty()) {
    return absl::InvalidArgumentError(
        "--timing-only needs --timing OUT.csv or --xdts OUT.xdts (the sheet it writes)");
  }
  if (args.timing_only && !args.output.empty()) {
    return absl::InvalidArgumentError("-o: --timing-only writes only the sheet; drop -o");
  }
  if (!args.timing_only && args.output.empty()) {
    return absl::InvalidArgumentError(
        "-o/--output OUT.motion3.json or OUT.csv is required (or --timing-only with --timing "
        "OUT.csv)");
  }
  return CheckOneOnStdout({{"-o", args.output},
                           {"--timing", args.timing},
                           {"--report", args.report},
                           {"--xdts", args.xdts}},
                          args.json);
}

absl::Status WriteCurvesOutputs(const CurvesArgs& args, const CurveInput& input,
                                const v1::RetimeCurvesResponse& response) {
  if (!args.timing_only) {
    std::vector<std::optional<CurveReplacement>> replacements;
    for (const v1::RetimedCurve& curve : response.curves()) {
      replacements.push_back(convert::ReplacementFromProto(curve));
    }
    if (replacements.size() != input.curves.curves.size()) {
      return absl::InternalError(absl::StrCat("the server answered ", replacements.size(),
                                              " curves for ", input.curves.curves.size()));
    }
    if (absl::Status s =
            WriteCurveOutput(args.output, input, replacements, CurveFormatFromFlag(args.format));
        !s.ok()) {
      return s;
    }
  }
  if (!args.timing.empty() && response.timings_size() > 0) {
    const std::string sheet =
        formats::WriteDrawingSheetCsv(TimingFromProto(response.timings(0)), input.curves.fps);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return s;
  }
  if (!args.xdts.empty()) {
    absl::StatusOr<formats::XdtsSheet> sheet =
        CurvesXdtsSheet(response, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return sheet.status();
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) return s;
  }
  return absl::OkStatus();
}

int RunCurves(const CurvesArgs& args) {
  const CommandOutput out("curves", args.json, args.quiet, args.server);
  if (absl::Status s = CheckCurvesFlags(args); !s.ok()) return out.UsageFailure(s);
  absl::StatusOr<CurveInput> input =
      ReadCurveInput(args.input, args.csv_fps, CurveFormat::kAuto, "curves");
  if (!input.ok()) return out.Failure(input.status());
  if (!args.timing_only) {
    absl::StatusOr<CurveFormat> format =
        CurveOutputFormat(args.output, CurveFormatFromFlag(args.format), *input);
    if (!format.ok()) return out.UsageFailure(format.status());
  }
  absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args, input->curves);
  if (!request.ok()) return out.UsageFailure(request.status());
  // --send-file: the wire carries the file; the report still reads the decoded request.
  std::optional<v1::RetimeCurvesRequest> file_request;
  if (args.send_file) {
    absl::StatusOr<v1::RetimeCurvesRequest> with_file = BuildCurvesFileRequest(args, *input);
    if (!with_file.ok()) return out.UsageFailure(with_file.status());
    file_request = *std::move(with_file);
  }
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report, args.xdts}); !s.ok())
    return out.Failure(s);

  v1::RetimeCurvesResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeCurves,
                            file_request ? *file_request : *request, &response);
      code >= 0) {
    return code;
  }

  if (absl::Status s = WriteCurvesOutputs(args, *input, response); !s.ok()) return out.Failure(s);
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteCurvesReport(args.report, *request, response, args.input);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(CurvesSummaryText(args, input->curves, response) + XdtsLine(args.xdts) +
                  ReportLine(args.report),
              CurvesSummaryJson(args, input->curves, response),
              IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) ||
                  IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

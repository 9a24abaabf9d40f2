#include "client/curves_command.h"

#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/channel.h"
#include "client/curve_files.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/report/curves_report.h"
#include "formats/drawing_sheet.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

constexpr int kUsageError = 2;

// "ParamHair=2" -> request.curve_overrides; false on a malformed entry.
bool AddCurveOverrides(const std::vector<std::string>& entries, v1::RetimeCurvesRequest& request) {
  for (const std::string& entry : entries) {
    const size_t equals = entry.rfind('=');
    int n = 0;
    if (equals == std::string::npos || equals == 0 ||
        !absl::SimpleAtoi(entry.substr(equals + 1), &n)) {
      std::fprintf(stderr, "koma: --curve-on %s: expected ID=N, e.g. ParamHair=2\n", entry.c_str());
      return false;
    }
    v1::CurveOverride* o = request.add_curve_overrides();
    o->set_curve_id(entry.substr(0, equals));
    o->set_frames_per_drawing(n);
  }
  return true;
}

v1::RetimeCurvesRequest MakeRequest(const CurvesArgs& args, const CurveSet& curves) {
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  request.mutable_key_frames()->Add(args.keys.begin(), args.keys.end());
  if (args.frames_per_drawing) request.set_frames_per_drawing(*args.frames_per_drawing);
  if (args.tame) request.set_tame(*args.tame);
  if (args.tsume) request.set_tsume(*args.tsume);
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  return request;
}

absl::Status WriteOutput(const CurvesArgs& args, const CurveInput& input,
                         const v1::RetimeCurvesResponse& response) {
  std::vector<std::optional<CurveReplacement>> replacements;
  for (const v1::RetimedCurve& curve : response.curves()) {
    replacements.push_back(
        CurveReplacement{std::vector<double>(curve.values().begin(), curve.values().end()),
                         StepsFromProto(curve.stepped())});
  }
  return WriteCurveOutput(args.output, input, replacements);
}

// "on ones", "on twos", "on threes", then "on 4s".
std::string OnName(int n) {
  switch (n) {
    case 1:
      return "on ones";
    case 2:
      return "on twos";
    case 3:
      return "on threes";
    default:
      return absl::StrCat("on ", n, "s");
  }
}

std::string Histogram(const v1::RetimedCurve& curve) {
  std::vector<std::string> parts;
  for (const v1::HoldCount& c : curve.hold_histogram()) {
    parts.push_back(absl::StrCat(c.drawings(), " x ", c.length(), "f"));
  }
  return absl::StrJoin(parts, ", ");
}

void PrintSummary(const CurvesArgs& args, const CurveSet& curves,
                  const v1::RetimeCurvesResponse& response) {
  std::printf("%s: %zu curves, %d frames at %.4g fps -> %s\n", args.input.c_str(),
              curves.curves.size(), curves.frame_count, curves.fps, args.output.c_str());
  std::printf("  key poses (%d): %s\n", response.key_frames_size(),
              absl::StrJoin(response.key_frames(), ", ").c_str());
  if (response.timing_fps() > 0) {
    std::printf(
        "  on the %.4g fps film grid (holds in its frames, %.1f ms each); key poses at "
        "grid frames %s\n",
        response.timing_fps(), 1000.0 / response.timing_fps(),
        absl::StrJoin(response.key_grid_frames(), ", ").c_str());
  }
  std::map<int, std::vector<std::string>> curves_by_timing;
  for (const v1::RetimedCurve& curve : response.curves()) {
    curves_by_timing[curve.timing()].push_back(curve.id());
  }
  for (const auto& [index, ids] : curves_by_timing) {
    const v1::DrawingTiming& timing = response.timings(index);
    const v1::RetimedCurve* first = nullptr;
    for (const v1::RetimedCurve& curve : response.curves()) {
      if (curve.timing() == index) {
        first = &curve;
        break;
      }
    }
    std::printf("  %s: %d drawings (holds %s) for %s\n",
                OnName(timing.frames_per_drawing()).c_str(), timing.drawing_start_size(),
                Histogram(*first).c_str(), absl::StrJoin(ids, ", ").c_str());
  }
  if (!args.timing.empty()) std::printf("  drawing sheet: %s\n", args.timing.c_str());
}

}  // namespace

int RunCurves(const CurvesArgs& args) {
  if (!CanWriteOutput(args.input, args.output)) return kUsageError;
  absl::StatusOr<CurveInput> input = ReadCurveInput(args.input, args.csv_fps);
  if (!input.ok()) return ReportError(input.status());
  v1::RetimeCurvesRequest request = MakeRequest(args, input->curves);
  if (!AddCurveOverrides(args.curve_on, request)) return kUsageError;
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report}); !s.ok()) {
    return ReportError(s);
  }

  absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> stub = NewRetimeStub(args.server);
  if (!stub.ok()) return ReportError(stub.status());
  grpc::ClientContext context;
  SetDeadline(&context, args.deadline_seconds);
  v1::RetimeCurvesResponse response;
  const grpc::Status status = (*stub)->RetimeCurves(&context, request, &response);
  if (!status.ok()) return ReportRpcError(status);

  if (absl::Status s = WriteOutput(args, *input, response); !s.ok()) return ReportError(s);
  if (!args.timing.empty()) {
    const std::string sheet =
        formats::WriteDrawingSheetCsv(TimingFromProto(response.timings(0)), input->curves.fps);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return ReportError(s);
  }
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteCurvesReport(args.report, request, response, args.input);
        !s.ok()) {
      return ReportError(s);
    }
  }
  PrintSummary(args, input->curves, response);
  if (!args.report.empty()) std::printf("  report: %s\n", args.report.c_str());
  return 0;
}

}  // namespace koma::client

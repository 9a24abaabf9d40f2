#include "client/spine_curves.h"

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/curves_convert.h"
#include "client/curves_summary.h"
#include "client/files.h"
#include "client/report/curves_report.h"
#include "client/retime_call.h"
#include "client/xdts_sheets.h"
#include "convert/curves_convert.h"
#include "formats/drawing_sheet.h"
#include "formats/error_text.h"
#include "formats/spine.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {

absl::StatusOr<std::vector<int>> SpineAnimationsToRetime(const CurveInput& input,
                                                         const std::vector<std::string>& names) {
  const formats::SpineFile& file = *input.spine;
  std::vector<int> indices;
  for (const std::string& name : names) {
    absl::StatusOr<int> index = formats::FindSpineAnimation(file, name);
    if (!index.ok()) return absl::NotFoundError(absl::StrCat("--animation: ", index.status().message()));
    if (!file.animations[*index].retimable()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--animation: ", formats::QuoteForError(name),
          " has no bone rotate, translate, scale or shear keys to retime"));
    }
    if (std::find(indices.begin(), indices.end(), *index) == indices.end()) {
      indices.push_back(*index);
    }
  }
  if (!names.empty()) return indices;
  for (size_t i = 0; i < file.animations.size(); ++i) {
    if (file.animations[i].retimable()) indices.push_back(static_cast<int>(i));
  }
  if (indices.empty()) {
    return absl::InvalidArgumentError(
        "the skeleton has no animation with bone rotate, translate, scale or shear keys to retime");
  }
  return indices;
}

absl::Status SelectOneSpineAnimation(CurveInput& input, const std::vector<std::string>& names) {
  absl::StatusOr<std::vector<int>> indices = SpineAnimationsToRetime(input, names);
  if (!indices.ok()) return indices.status();
  if (indices->size() != 1) {
    std::vector<std::string> quoted;
    for (const int i : *indices) quoted.push_back(formats::QuoteForError(input.spine->animations[i].name));
    return absl::InvalidArgumentError(absl::StrCat(
        "--animation: one animation per skeleton here; this one has ", indices->size(),
        " with bone keys (", absl::StrJoin(quoted, ", "), ")"));
  }
  return convert::SelectSpineAnimation(input, indices->front());
}

int RunSpineCurves(const CurvesArgs& args, const CurveInput& input, const CommandOutput& out) {
  absl::StatusOr<std::vector<int>> indices = SpineAnimationsToRetime(input, args.animations);
  if (!indices.ok()) return out.Failure(indices.status());
  const bool one = indices->size() == 1;
  if (!args.timing.empty() && !one) {
    return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
        "--timing: the drawing sheet is per animation; name one with --animation (this run "
        "retimes ", indices->size(), ")")));
  }
  if (!args.report.empty() && !one) {
    return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
        "--report: the report is per animation; name one with --animation (this run retimes ",
        indices->size(), ")")));
  }
  if (!args.xdts.empty() && !one) {
    return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
        "--xdts: the exposure sheet is per animation; name one with --animation (this run "
        "retimes ", indices->size(), ")")));
  }
  if (!args.timing_only && (IsCsvPath(args.output) || args.format == "csv" ||
                            args.format == "motion3")) {
    return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
        "-o ", args.output, ": a Spine skeleton is written back as Spine JSON (-o OUT.json)")));
  }
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report, args.xdts}); !s.ok()) {
    return out.Failure(s);
  }

  // --curve-on ID=N: applied to the animations that have the curve; an id none has is a typo.
  for (const std::string& entry : args.curve_on) {
    const std::string id = entry.substr(0, entry.rfind('='));
    bool found = false;
    for (const int index : *indices) {
      for (const Curve& curve : input.spine->animations[index].curves.curves) {
        found = found || curve.id == id;
      }
    }
    if (!found) {
      return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
          "--curve-on: no animation retimed here has the curve ", formats::QuoteForError(id),
          " (ids are BONE/rotate, BONE/translate.x, BONE/scale.y, BONE/shear.x, ...)")));
    }
  }

  std::vector<formats::SpineRetimed> retimed;
  std::string text;
  nlohmann::json summary;
  nlohmann::json animations = nlohmann::json::array();
  std::string file_text = input.text;  // --send-file: each call carries the previous answer
  for (const int index : *indices) {
    CurveInput selected = input;
    if (absl::Status s = convert::SelectSpineAnimation(selected, index); !s.ok()) {
      return out.Failure(s);
    }
    const std::string& name = input.spine->animations[index].name;
    CurvesArgs animation_args = args;
    animation_args.curve_on.clear();
    for (const std::string& entry : args.curve_on) {
      const std::string id = entry.substr(0, entry.rfind('='));
      for (const Curve& curve : selected.curves.curves) {
        if (curve.id == id) animation_args.curve_on.push_back(entry);
      }
    }
    animation_args.send_file = false;
    absl::StatusOr<v1::RetimeCurvesRequest> request =
        BuildCurvesFileRequest(animation_args, selected);
    if (!request.ok()) return out.UsageFailure(request.status());
    // --send-file: the wire carries the skeleton (as the previous call left it) and the
    // animation's name; the report still reads the decoded request.
    v1::RetimeCurvesRequest sent = *request;
    if (args.send_file) {
      selected.text = file_text;
      animation_args.send_file = true;
      absl::StatusOr<v1::RetimeCurvesRequest> with_file =
          BuildCurvesFileRequest(animation_args, selected);
      if (!with_file.ok()) return out.UsageFailure(with_file.status());
      sent = *std::move(with_file);
    }
    v1::RetimeCurvesResponse response;
    if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeCurves, sent, &response);
        code >= 0) {
      return code;
    }
    if (args.send_file) file_text = response.spine_json();
    if (response.curves_size() != static_cast<int>(selected.curves.curves.size())) {
      return out.Failure(absl::InternalError(
          absl::StrCat("the server answered ", response.curves_size(), " curves for ",
                       selected.curves.curves.size(), " of animation ", name)));
    }
    formats::SpineRetimed one_retimed{index, {}};
    for (const v1::RetimedCurve& curve : response.curves()) {
      // A GROUP_KEEP curve (timing -1, no stepped keys) keeps its timeline as it came in, as
      // the server writes it (its stepped keys would be one key at 0 s, value 0).
      if (curve.timing() < 0) {
        one_retimed.stepped.emplace_back();
      } else {
        one_retimed.stepped.push_back(convert::ReplacementFromProto(curve).steps);
      }
    }
    retimed.push_back(std::move(one_retimed));
    text += absl::StrCat("animation ", formats::QuoteForError(name), ":\n",
                         CurvesSummaryText(args, selected.curves, *request, response));
    nlohmann::json animation_summary = CurvesSummaryJson(args, selected.curves, *request, response);
    animation_summary["animation"] = name;
    if (summary.is_null()) summary = animation_summary;
    animations.push_back(std::move(animation_summary));
    if (!args.timing.empty() && response.timings_size() > 0) {
      const DrawingTiming timing = TimingFromProto(response.timings(0));
      const std::string sheet = formats::WriteDrawingSheetCsv(
          {"body", &timing, convert::KeysByDrawing(response, 0)}, selected.curves.fps);
      if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return out.Failure(s);
    }
    if (!args.xdts.empty()) {
      // The cut is named after the file and the animation ("hero/walk").
      absl::StatusOr<formats::XdtsSheet> sheet = CurvesXdtsSheet(
          response, absl::StrCat(XdtsClipName(args.input, args.xdts), "/", name));
      if (!sheet.ok()) return out.Failure(sheet.status());
      if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) {
        return out.Failure(s);
      }
    }
    if (!args.report.empty()) {
      if (absl::Status s = report::WriteCurvesReport(args.report, *request, response,
                                                     absl::StrCat(args.input, " (", name, ")"));
          !s.ok()) {
        return out.Failure(s);
      }
    }
  }
  if (!args.timing_only) {
    absl::StatusOr<std::string> written = formats::WriteSpine(*input.spine, retimed);
    if (!written.ok()) return out.Failure(written.status());
    if (absl::Status s = WriteFile(args.output, *written); !s.ok()) return out.Failure(s);
  }
  summary["animations"] = std::move(animations);
  out.Success(text + XdtsLine(args.xdts) + ReportLine(args.report), summary,
              IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) ||
                  IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

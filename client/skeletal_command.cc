#include "client/skeletal_command.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "client/file_format.h"
#include "client/files.h"
#include "client/flag_values.h"
#include "client/report/skeletal_report.h"
#include "client/retime_call.h"
#include "client/skeletal_convert.h"
#include "client/skeletal_file_formats.h"
#include "client/skeletal_gltf.h"
#include "client/skeletal_summary.h"
#include "client/timing_from.h"
#include "client/xdts_sheets.h"
#include "core/film_grid.h"
#include "formats/bvh.h"
#include "formats/timing_sheet.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

// --joint-weights: "1,1,0.5,..." (one per joint, in file order) or "Hips=0,Head=2,..." (by
// name, the others 1).
absl::StatusOr<std::vector<double>> JointWeights(const std::vector<std::string>& entries,
                                                 const Skeleton& skeleton) {
  constexpr char kFlag[] = "--joint-weights";
  std::vector<double> weights;
  if (entries.empty()) return weights;
  const bool by_name = entries[0].find('=') != std::string::npos;
  if (!by_name) {
    for (const std::string& entry : entries) {
      absl::StatusOr<double> w = ParseNumber(kFlag, entry, AtLeast(0));
      if (!w.ok()) return w.status();
      weights.push_back(*w);
    }
    if (weights.size() != skeleton.joints.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat(kFlag, ": ", weights.size(), " weights for ", skeleton.joints.size(),
                       " joints: give one per joint in file order, or NAME=W for some joints"));
    }
    return weights;
  }
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < skeleton.joints.size(); ++i) index_of[skeleton.joints[i].name] = i;
  weights.assign(skeleton.joints.size(), 1.0);
  for (const std::string& entry : entries) {
    const size_t equals = entry.rfind('=');
    if (equals == std::string::npos || equals == 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          kFlag, ": \"", entry, "\" is not NAME=WEIGHT (do not mix names and plain weights)"));
    }
    const std::string name = entry.substr(0, equals);
    const auto it = index_of.find(name);
    if (it == index_of.end()) {
      std::vector<std::string> names;
      for (const Joint& joint : skeleton.joints) names.push_back(joint.name);
      const std::string close = ClosestMatch(name, names);
      return absl::InvalidArgumentError(
          absl::StrCat(kFlag, ": the clip has no joint \"", name, "\"",
                       close.empty() ? "" : absl::StrCat("; did you mean \"", close, "\"?")));
    }
    absl::StatusOr<double> w = ParseNumber(kFlag, entry.substr(equals + 1), AtLeast(0));
    if (!w.ok()) return w.status();
    weights[it->second] = *w;
  }
  return weights;
}

}  // namespace

absl::StatusOr<SkeletalInput> ReadSkeletalFile(const std::string& path) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  return ParseSkeletalText(path, *std::move(text));
}

absl::StatusOr<SkeletalInput> ParseSkeletalText(const std::string& path, std::string text_in) {
  std::optional<std::string> text(std::move(text_in));
  if (absl::Status s = CheckInputFormat(path, *text, "skeletal"); !s.ok()) return s;
  if (IsGltfInput(path, *text)) {
    return absl::InvalidArgumentError(
        absl::StrCat(InputName(path),
                     " is a glTF file: `koma skeletal IN.glb -o OUT.glb` retimes it whole "
                     "(this step reads BVH only)"));
  }
  std::vector<std::string> warnings;
  absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(*text, &warnings);
  if (!clip.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(InputName(path), " (BVH): ", clip.status().message()));
  }
  for (std::string& warning : warnings) warning.insert(0, InputName(path) + " (BVH): ");
  return SkeletalInput{*std::move(clip), *std::move(text), std::move(warnings)};
}

absl::StatusOr<SkeletalClip> ReadSkeletalInput(const std::string& path) {
  absl::StatusOr<SkeletalInput> input = ReadSkeletalFile(path);
  if (!input.ok()) return input.status();
  return std::move(input->clip);
}

void SetSkeletalOptions(const SkeletalArgs& args, v1::RetimeSkeletalRequest* request) {
  if (args.omissions) request->set_omissions(*args.omissions);
  if (args.holds) request->set_holds(*args.holds);
  if (args.max_hold) request->set_max_hold(*args.max_hold);
  request->set_keep_length(args.keep_length);
  if (!args.order.empty()) {
    request->set_order(args.order == "hold-then-omit" ? v1::HOLD_THEN_OMIT : v1::OMIT_THEN_HOLD);
  } else {
    request->set_order(args.hold_first ? v1::HOLD_THEN_OMIT : v1::OMIT_THEN_HOLD);
  }
  request->set_root_relative(args.root_relative);
  request->mutable_camera()->Add(args.camera.begin(), args.camera.end());
  if (args.timing_only) {
    request->set_return_motion(false);
  } else if (args.return_motion) {
    request->set_return_motion(*args.return_motion);
  }
  if (args.timing_fps) request->set_timing_fps(*args.timing_fps);
  if (args.output_at_timing_rate) request->set_output_rate(v1::TIMING_RATE);
  if (args.omissions_per_second) request->set_omissions_per_second(*args.omissions_per_second);
  if (args.drawings_per_second) request->set_drawings_per_second(*args.drawings_per_second);
  if (args.cut_neighbour_ratio) request->set_cut_neighbour_ratio(*args.cut_neighbour_ratio);
  if (args.cut_median_ratio) request->set_cut_median_ratio(*args.cut_median_ratio);
}

absl::StatusOr<v1::RetimeSkeletalRequest> BuildSkeletalRequest(const SkeletalArgs& args,
                                                               const SkeletalClip& clip) {
  v1::RetimeSkeletalRequest request;
  *request.mutable_motion() = ToProto(clip);
  SetSkeletalOptions(args, &request);
  absl::StatusOr<std::vector<double>> weights = JointWeights(args.joint_weights, clip.skeleton);
  if (!weights.ok()) return weights.status();
  request.mutable_joint_weights()->Add(weights->begin(), weights->end());
  return request;
}

absl::Status SetSkeletalTimingFromArgs(const SkeletalArgs& args, const SkeletalClip& clip,
                                       v1::RetimeSkeletalRequest* request,
                                       std::vector<std::string>* warnings) {
  if (args.timing_from.empty()) return absl::OkStatus();
  const SkeletalClipShape shape{clip.frame_count, clip.frame_time > 0 ? 1.0 / clip.frame_time : 0.0,
                                args.timing_fps};
  return SetSkeletalTimingFrom(args.timing_from, XdtsClipName(args.input, ""), shape, request,
                               warnings);
}

absl::StatusOr<v1::RetimeSkeletalRequest> BuildSkeletalFileRequest(const SkeletalArgs& args,
                                                                   const SkeletalInput& input) {
  absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildSkeletalRequest(args, input.clip);
  if (!request.ok() || !args.send_file) return request;
  request->clear_motion();
  request->set_bvh_text(input.text);
  return request;
}

absl::Status CheckSkeletalFlags(const SkeletalArgs& args) {
  const bool motion_wanted = !args.timing_only && args.return_motion.value_or(true);
  const bool sheet_wanted = !args.timing.empty() || !args.xdts.empty();
  if (args.timing_only && !sheet_wanted) {
    return absl::InvalidArgumentError(
        "--timing-only needs --timing OUT.csv or --xdts OUT.xdts (the sheet it writes)");
  }
  if (motion_wanted && args.output.empty()) {
    return absl::InvalidArgumentError(
        "-o/--output OUT.bvh is required (or --timing-only with --timing OUT.csv)");
  }
  if (!motion_wanted && !args.output.empty()) {
    return absl::InvalidArgumentError(
        "-o: no motion is asked for (--timing-only or --return-motion false), so there is "
        "nothing to write there; drop -o");
  }
  if (!sheet_wanted && !motion_wanted) {
    return absl::InvalidArgumentError(
        "--return-motion false needs --timing OUT.csv or --xdts OUT.xdts");
  }
  if (absl::Status s = CheckOneOnStdout({{"-o", args.output},
                                         {"--timing", args.timing},
                                         {"--report", args.report},
                                         {"--xdts", args.xdts}},
                                        args.json);
      !s.ok()) {
    return s;
  }
  if (IsStdio(args.input) && IsStdio(args.timing_from)) {
    return absl::InvalidArgumentError(
        "--timing-from -: the input is standard input already; give the sheet's path");
  }
  if (args.omissions && args.omissions_per_second) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--omit ", *args.omissions, " and --omissions-per-second ", *args.omissions_per_second,
        ": give one (a --config file may have set the other)"));
  }
  // A name of a format other commands write (motion3.json, CSV), not a name koma has no
  // format for (a BVH may be written to any name).
  const formats::FormatRow& named = formats::FormatOf(FormatFromName(args.output));
  if (!named.written_by.empty() && !formats::WrittenBy(named, "skeletal")) {
    return absl::InvalidArgumentError(
        absl::StrCat("-o ", args.output,
                     ": koma skeletal writes BVH (-o OUT.bvh) or, for a glTF or FBX "
                     "input, the same format (-o OUT.glb, -o OUT.fbx)"));
  }
  return absl::OkStatus();
}

absl::Status WriteSkeletalXdts(const SkeletalArgs& args,
                               const v1::RetimeSkeletalResponse& response) {
  absl::StatusOr<formats::XdtsSheet> sheet =
      SkeletalXdtsSheet(response, XdtsClipName(args.input, args.xdts));
  if (!sheet.ok()) return sheet.status();
  return WriteFile(args.xdts, formats::WriteXdts(*sheet));
}

absl::Status WriteSkeletalOutputs(const SkeletalArgs& args, const SkeletalClip& clip,
                                  const v1::RetimeSkeletalResponse& response) {
  if (!args.output.empty() && !args.timing_only && !response.bvh_text().empty()) {
    // The server wrote the file (--send-file): byte for byte what the writer below gives.
    if (absl::Status s = WriteFile(args.output, response.bvh_text()); !s.ok()) return s;
  } else if (!args.output.empty() && !args.timing_only && response.has_motion()) {
    absl::StatusOr<SkeletalClip> retimed = ClipFromResponse(response, clip.skeleton);
    if (!retimed.ok()) return retimed.status();
    if (absl::Status s = WriteFile(args.output, formats::WriteBvh(*retimed)); !s.ok()) return s;
  }
  if (!args.timing.empty()) {
    const std::vector<int32_t> grid_frames(response.grid_frames().begin(),
                                           response.grid_frames().end());
    double frame_time = clip.frame_time;
    if (response.has_motion()) {
      frame_time = response.motion().frame_time();
    } else if (args.output_at_timing_rate && response.timing_fps() > 0) {
      frame_time = 1.0 / response.timing_fps();
    }
    // Times on the rate koma recognises (the film's, or a whole fps within the grid's 1e-4):
    // frame 72 of a 0.0416667 s Frame Time is at 3 s, not 3.0000024.
    const double film_fps = response.timing_fps() > 0 ? response.timing_fps()
                                                      : args.timing_fps.value_or(kDefaultTimingFps);
    const std::string sheet =
        formats::WriteTimingSheetCsv(TimingMapFromResponse(response), frame_time,
                                     response.timing_fps() > 0 ? &grid_frames : nullptr,
                                     formats::RecognisedFps(frame_time, film_fps));
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return s;
  }
  if (!args.xdts.empty()) {
    if (absl::Status s = WriteSkeletalXdts(args, response); !s.ok()) return s;
  }
  return absl::OkStatus();
}

int RunSkeletal(const SkeletalArgs& args) {
  const CommandOutput out("skeletal", args.json, args.quiet, args.server);
  if (absl::Status s = CheckSkeletalFlags(args); !s.ok()) return out.UsageFailure(s);
  if (absl::Status s = CheckWritable({args.output, args.timing, args.report, args.xdts}); !s.ok())
    return out.Failure(s);
  absl::StatusOr<std::string> bytes = ReadFile(args.input);
  if (!bytes.ok()) return out.Failure(bytes.status());
  if (const SkeletalFileFormat* file = SkeletalFileFormatOf(args.input, &*bytes)) {
    return file->run(args, *std::move(bytes));
  }
  if (!args.take.empty()) {
    return out.UsageFailure(absl::InvalidArgumentError("--take picks an FBX file's take; " +
                                                       InputName(args.input) + " is not FBX"));
  }
  if (HasGltfFlags(args)) {
    return out.UsageFailure(absl::InvalidArgumentError(
        "--gltf-animations, --gltf-retime-none, --gltf-source-fps, --gltf-keys and "
        "--gltf-keep-original are for glTF inputs; " +
        InputName(args.input) + " is not one"));
  }
  // -o names a format that only comes back from its own input (OUT.glb for IN.glb).
  if (const FormatId out_format = FormatFromName(args.output);
      out_format != FormatId::kBvh &&
      formats::WrittenBy(formats::FormatOf(out_format), "skeletal")) {
    return out.UsageFailure(absl::InvalidArgumentError(absl::StrCat(
        "-o ", args.output, ": the input is BVH, and koma skeletal writes BVH back (-o OUT.bvh)")));
  }
  absl::StatusOr<SkeletalInput> input = ParseSkeletalText(args.input, *std::move(bytes));
  if (!input.ok()) return out.Failure(input.status());
  const SkeletalClip* clip = &input->clip;
  absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildSkeletalRequest(args, *clip);
  if (!request.ok()) return out.UsageFailure(request.status());
  if (absl::Status s = SetSkeletalTimingFromArgs(args, *clip, &*request, &input->warnings);
      !s.ok()) {
    return out.Failure(s);
  }
  // --send-file: the wire carries the file; the report still reads the decoded request.
  std::optional<v1::RetimeSkeletalRequest> file_request;
  if (args.send_file) {
    file_request = *request;
    file_request->clear_motion();
    file_request->set_bvh_text(input->text);
  }
  v1::RetimeSkeletalResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeSkeletal,
                            file_request ? *file_request : *request, &response);
      code >= 0) {
    return code;
  }
  // The file's warnings as this client read it (with --send-file the server read the same
  // text and found the same, named after its field): one wording in summary, JSON and report.
  response.clear_warnings();
  for (const std::string& warning : input->warnings) response.add_warnings(warning);
  if (absl::Status s = WriteSkeletalOutputs(args, *clip, response); !s.ok()) return out.Failure(s);
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteSkeletalReport(args.report, *request, response, args.input);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(
      SkeletalSummaryText(args, *clip, response) + XdtsLine(args.xdts) + ReportLine(args.report),
      SkeletalSummaryJson(args, *clip, response),
      IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

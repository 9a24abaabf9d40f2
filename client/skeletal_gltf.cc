#include "client/skeletal_gltf.h"

#include <optional>
#include <utility>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/command_output.h"
#include "client/file_format.h"
#include "client/files.h"
#include "client/report/skeletal_report.h"
#include "client/retime_call.h"
#include "client/skeletal_convert.h"
#include "client/skeletal_summary.h"
#include "client/timing_from.h"
#include "client/xdts_sheets.h"
#include "convert/gltf_convert.h"
#include "core/status_macros.h"
#include "formats/gltf.h"
#include "formats/number_format.h"
#include "formats/timing_sheet.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

bool NamesGlbContainer(const std::string& path) {
  return absl::EndsWithIgnoreCase(path, ".glb") || absl::EndsWithIgnoreCase(path, ".vrm") ||
         absl::EndsWithIgnoreCase(path, ".vrma");
}

// The first animation's clip as the BVH summary reads it: joints, frames, rate.
SkeletalClip SummaryClip(const v1::GltfAnimationTiming& animation) {
  SkeletalClip clip;
  for (const std::string& name : animation.joints()) {
    Joint joint;
    joint.name = name;
    clip.skeleton.joints.push_back(std::move(joint));
  }
  clip.frame_count = animation.frame_count();
  clip.frame_time = 1.0 / animation.source_fps();
  return clip;
}

}  // namespace

bool IsGltfInput(const std::string& path, const std::string& bytes) {
  return FormatFromName(path) == FormatId::kGltf || SniffFormat(bytes) == FormatId::kGltf;
}

bool HasGltfFlags(const SkeletalArgs& args) {
  return !args.animations.empty() || args.retime_none || args.source_fps.has_value() ||
         !args.gltf_keys.empty() || args.keep_original;
}

absl::Status CheckGltfFlags(const SkeletalArgs& args, bool input_is_glb) {
  if (!args.joint_weights.empty() && args.joint_weights[0].find('=') != std::string::npos) {
    return absl::InvalidArgumentError(
        "--joint-weights: NAME=W needs the joints, which the server reads from a glTF file; "
        "give one weight per joint in the order of the summary's joints");
  }
  if (args.retime_none && !args.animations.empty()) {
    return absl::InvalidArgumentError(
        "--gltf-retime-none and --gltf-animations: give one or the other");
  }
  if (!args.output.empty() && !IsStdio(args.output)) {
    const FormatId named = FormatFromName(args.output);
    const bool glb_out = NamesGlbContainer(args.output);
    if (named != FormatId::kGltf || glb_out != input_is_glb) {
      return absl::InvalidArgumentError(absl::StrCat(
          "-o ", args.output, ": the input is ", input_is_glb ? "a GLB file" : "a .gltf file",
          ", and koma writes the same file back: -o OUT",
          input_is_glb ? ".glb (or .vrm, .vrma)" : ".gltf"));
    }
  }
  return absl::OkStatus();
}

absl::Status SetFileJointWeights(const SkeletalArgs& args, v1::RetimeSkeletalRequest* request) {
  for (const std::string& weight : args.joint_weights) {
    double w = 0;
    if (!absl::SimpleAtod(weight, &w)) {
      return absl::InvalidArgumentError(
          absl::StrCat("--joint-weights: \"", weight, "\" is not a number"));
    }
    request->add_joint_weights(w);
  }
  return absl::OkStatus();
}

absl::StatusOr<v1::RetimeSkeletalRequest> BuildGltfRequest(const SkeletalArgs& args,
                                                           std::string bytes) {
  v1::RetimeSkeletalRequest request;
  request.set_gltf(std::move(bytes));
  SetSkeletalOptions(args, &request);
  KOMA_RETURN_IF_ERROR(SetFileJointWeights(args, &request));
  if (!args.timing_from.empty()) {
    // The server reads the file: it checks the sheet's frames against the clip.
    if (absl::Status s = SetSkeletalTimingFrom(args.timing_from, XdtsClipName(args.input, ""),
                                               {}, &request, nullptr);
        !s.ok()) {
      return s;
    }
  }
  for (const std::string& animation : args.animations) request.add_gltf_animations(animation);
  request.set_gltf_retime_none(args.retime_none);
  if (args.source_fps) request.set_gltf_source_fps(*args.source_fps);
  if (args.gltf_keys == "linear") request.set_gltf_keys(v1::GLTF_KEYS_LINEAR);
  if (args.gltf_keys == "step") request.set_gltf_keys(v1::GLTF_KEYS_STEP);
  request.set_gltf_keep_original(args.keep_original);
  return request;
}

absl::Status WriteGltfOutputs(const SkeletalArgs& args,
                              const v1::RetimeSkeletalResponse& response) {
  if (!args.output.empty() && !args.timing_only) {
    if (absl::Status s = WriteFile(args.output, response.gltf()); !s.ok()) return s;
  }
  if (!args.timing.empty()) {
    if (response.gltf_animations_size() == 0) {
      return absl::FailedPreconditionError(
          absl::StrCat("--timing ", args.timing,
                       ": no animation was retimed, so there is no "
                       "timing sheet to write"));
    }
    const v1::GltfAnimationTiming& first = response.gltf_animations(0);
    const std::vector<int32_t> grid_frames(response.grid_frames().begin(),
                                           response.grid_frames().end());
    const std::string sheet =
        formats::WriteTimingSheetCsv(TimingMapFromResponse(response), 1.0 / first.output_fps(),
                                     response.timing_fps() > 0 ? &grid_frames : nullptr);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return s;
  }
  if (!args.xdts.empty()) {
    // The first retimed animation's timing, as --timing writes it.
    if (response.gltf_animations_size() == 0) {
      return absl::FailedPreconditionError(
          absl::StrCat("--xdts ", args.xdts,
                       ": no animation was retimed, so there is no "
                       "exposure sheet to write"));
    }
    if (absl::Status s = WriteSkeletalXdts(args, response); !s.ok()) return s;
  }
  return absl::OkStatus();
}

std::string GltfSummaryText(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response) {
  if (response.gltf_animations_size() == 0) {
    return absl::StrCat(InputName(args.input), ": no animation retimed",
                        args.output.empty() ? "" : absl::StrCat(" -> ", OutputName(args.output)),
                        " (the scene, meshes and extensions as they were)\n");
  }
  std::string text = SkeletalSummaryText(args, SummaryClip(response.gltf_animations(0)), response);
  const char* keys =
      args.gltf_keys == "linear" ? "LINEAR, one per output frame" : "STEP, one per drawing";
  for (const v1::GltfAnimationTiming& animation : response.gltf_animations()) {
    absl::StrAppend(
        &text, "  animation ", animation.index(), " \"", animation.name(),
        "\": ", animation.frame_count(), " frames at ",
        formats::FormatDouble(animation.source_fps()), " fps from ",
        formats::FormatDouble(animation.start_s()), " s; ", animation.timing().omissions_applied(),
        " omitted, ", animation.timing().holds_applied(), " holds; ", animation.keys_written(),
        " keys per channel (", keys, ")",
        args.keep_original ? absl::StrCat(" as \"", animation.name(), ".anime\"") : "", "\n");
  }
  return text;
}

absl::Status WriteGltfReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                             const v1::RetimeSkeletalResponse& response, const std::string& input) {
  if (response.gltf_animations_size() == 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("--report ", path, ": no animation was retimed"));
  }
  // The skin's joints as the server measured them: the file is read here too.
  absl::StatusOr<formats::GltfDocument> document = formats::ReadGltf(request.gltf());
  if (!document.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(InputName(input), " (glTF): ", document.status().message()));
  }
  const v1::GltfAnimationTiming& first = response.gltf_animations(0);
  v1::RetimeSkeletalRequest shown = request;
  shown.clear_gltf();
  *shown.mutable_motion() =
      convert::GltfMotion(*document, first.index(), first.source_fps(), first.frame_count());
  return report::WriteSkeletalReport(path, shown, first.timing(), input);
}

int RunSkeletalGltf(const SkeletalArgs& args, std::string bytes) {
  const CommandOutput out("skeletal", args.json, args.quiet, args.server);
  if (absl::Status s = CheckGltfFlags(
          args, SniffFormat(bytes) == FormatId::kGltf && absl::StartsWith(bytes, "glTF"));
      !s.ok()) {
    return out.UsageFailure(s);
  }
  absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildGltfRequest(args, std::move(bytes));
  if (!request.ok()) return out.UsageFailure(request.status());
  v1::RetimeSkeletalResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeSkeletal, *request, &response);
      code >= 0) {
    return code;
  }
  if (absl::Status s = WriteGltfOutputs(args, response); !s.ok()) return out.Failure(s);
  if (!args.report.empty()) {
    if (absl::Status s = WriteGltfReport(args.report, *request, response, args.input); !s.ok()) {
      return out.Failure(s);
    }
  }
  nlohmann::json json;
  if (response.gltf_animations_size() > 0) {
    json = SkeletalSummaryJson(args, SummaryClip(response.gltf_animations(0)), response);
  }
  out.Success(
      GltfSummaryText(args, response) + XdtsLine(args.xdts) + ReportLine(args.report), json,
      IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

#include "client/skeletal_fbx.h"

#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/command_output.h"
#include "client/file_format.h"
#include "client/files.h"
#include "client/report/skeletal_report.h"
#include "client/retime_call.h"
#include "client/skeletal_convert.h"
#include "client/skeletal_gltf.h"
#include "client/skeletal_summary.h"
#include "client/timing_from.h"
#include "client/xdts_sheets.h"
#include "convert/fbx_convert.h"
#include "formats/fbx.h"
#include "formats/fbx_scene.h"
#include "formats/number_format.h"
#include "formats/timing_sheet.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

// The take as the BVH summary reads a clip: its models, frames and rate.
SkeletalClip SummaryClip(const v1::FbxTakeTiming& take) {
  SkeletalClip clip;
  for (const std::string& name : take.joints()) {
    Joint joint;
    joint.name = name;
    clip.skeleton.joints.push_back(std::move(joint));
  }
  clip.frame_count = take.frame_count();
  clip.frame_time = 1.0 / take.source_fps();
  return clip;
}

absl::Status CheckFbxFlags(const SkeletalArgs& args) {
  if (HasGltfFlags(args)) {
    return absl::InvalidArgumentError(
        "--gltf-animations, --gltf-retime-none, --gltf-source-fps, --gltf-keys and "
        "--gltf-keep-original are for glTF inputs; " +
        InputName(args.input) + " is FBX (pick its take with --take)");
  }
  if (args.send_file) {
    return absl::InvalidArgumentError("--send-file: an FBX file always travels whole");
  }
  if (!args.output.empty() && !IsStdio(args.output) &&
      FormatFromName(args.output) != FormatId::kFbx) {
    return absl::InvalidArgumentError(absl::StrCat(
        "-o ", args.output, ": the input is FBX, and koma writes the same file back: -o OUT.fbx"));
  }
  return absl::OkStatus();
}

std::string FbxSummaryText(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response) {
  const v1::FbxTakeTiming& take = response.fbx_take();
  std::string text = SkeletalSummaryText(args, SummaryClip(take), response);
  absl::StrAppend(&text, "  take \"", take.name(), "\": ", take.frame_count(), " frames at ",
                  formats::FormatDouble(take.source_fps()), " fps from ",
                  formats::FormatDouble(take.start_s()), " s; ", take.curves_written(),
                  " curves keyed on every output frame (constant keys) at ",
                  formats::FormatDouble(take.output_fps()), " fps\n");
  return text;
}

}  // namespace

absl::StatusOr<v1::RetimeSkeletalRequest> BuildFbxRequest(const SkeletalArgs& args,
                                                          std::string bytes) {
  v1::RetimeSkeletalRequest request;
  request.set_fbx(std::move(bytes));
  request.set_fbx_take(args.take);
  SetSkeletalOptions(args, &request);
  if (absl::Status s = SetFileJointWeights(args, &request); !s.ok()) return s;
  if (!args.timing_from.empty()) {
    // The server reads the file: it checks the sheet's frames against the clip.
    if (absl::Status s = SetSkeletalTimingFrom(args.timing_from, XdtsClipName(args.input, ""),
                                               {}, &request, nullptr);
        !s.ok()) {
      return s;
    }
  }
  return request;
}

absl::Status WriteFbxOutputs(const SkeletalArgs& args, const v1::RetimeSkeletalResponse& response) {
  if (!args.output.empty() && !args.timing_only) {
    if (absl::Status s = WriteFile(args.output, response.fbx()); !s.ok()) return s;
  }
  if (!args.timing.empty()) {
    const std::vector<int32_t> grid_frames(response.grid_frames().begin(),
                                           response.grid_frames().end());
    const std::string sheet = formats::WriteTimingSheetCsv(
        TimingMapFromResponse(response), 1.0 / response.fbx_take().output_fps(),
        response.timing_fps() > 0 ? &grid_frames : nullptr);
    if (absl::Status s = WriteFile(args.timing, sheet); !s.ok()) return s;
  }
  if (!args.xdts.empty()) {
    if (absl::Status s = WriteSkeletalXdts(args, response); !s.ok()) return s;
  }
  return absl::OkStatus();
}

// The report's clip: the take's models' world positions, evaluated here as the server did.
absl::Status WriteFbxReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                            const v1::RetimeSkeletalResponse& response, const std::string& input) {
  absl::StatusOr<formats::FbxDocument> document = formats::ReadFbx(request.fbx());
  if (!document.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(InputName(input), " (FBX): ", document.status().message()));
  }
  absl::StatusOr<formats::FbxTakeRig> rig =
      formats::ReadFbxTakeRig(*document, response.fbx_take().name());
  if (!rig.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(InputName(input), " (FBX): ", rig.status().message()));
  }
  v1::RetimeSkeletalRequest shown = request;
  shown.clear_fbx();
  *shown.mutable_motion() = convert::FbxMotion(*rig, response.fbx_take().frame_count());
  return report::WriteSkeletalReport(path, shown, response, input);
}

bool IsFbxInput(const std::string& path, const std::string& bytes) {
  return FormatFromName(path) == FormatId::kFbx || SniffFormat(bytes) == FormatId::kFbx;
}

int RunSkeletalFbx(const SkeletalArgs& args, std::string bytes) {
  const CommandOutput out("skeletal", args.json, args.quiet, args.server);
  if (absl::Status s = CheckFbxFlags(args); !s.ok()) return out.UsageFailure(s);
  absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildFbxRequest(args, std::move(bytes));
  if (!request.ok()) return out.UsageFailure(request.status());
  v1::RetimeSkeletalResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::RetimeSkeletal, *request, &response);
      code >= 0) {
    return code;
  }
  if (absl::Status s = WriteFbxOutputs(args, response); !s.ok()) return out.Failure(s);
  if (!args.report.empty()) {
    if (absl::Status s = WriteFbxReport(args.report, *request, response, args.input); !s.ok()) {
      return out.Failure(s);
    }
  }
  const nlohmann::json json = SkeletalSummaryJson(args, SummaryClip(response.fbx_take()), response);
  out.Success(
      FbxSummaryText(args, response) + XdtsLine(args.xdts) + ReportLine(args.report), json,
      IsStdio(args.output) || IsStdio(args.timing) || IsStdio(args.report) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client

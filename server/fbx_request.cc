#include "server/fbx_request.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "convert/fbx_convert.h"
#include "core/fbx_rig.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/fbx.h"
#include "formats/fbx_scene.h"
#include "server/call_footprint.h"
#include "server/call_reservation.h"
#include "server/skeletal_request.h"

namespace koma::server {
namespace {

absl::Status InFbx(const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat("fbx: ", status.message()));
}

}  // namespace

absl::Status HandleRetimeSkeletalFbx(const v1::RetimeSkeletalRequest& request,
                                     const RequestLimits& limits,
                                     v1::RetimeSkeletalResponse* response,
                                     SkeletalAnswer* described) {
  const std::string& bytes = request.fbx();
  if (static_cast<int64_t>(bytes.size()) > limits.max_file_bytes) {
    return absl::ResourceExhaustedError(
        absl::StrCat("fbx: ", bytes.size(),
                     " bytes exceeds the server limit --max_file_bytes=", limits.max_file_bytes));
  }
  formats::FbxReadLimits read_limits;
  read_limits.max_inflated_bytes = std::max<int64_t>(limits.max_values, 1) * 16;
  absl::StatusOr<formats::FbxDocument> document = formats::ReadFbx(bytes, read_limits);
  if (!document.ok()) return InFbx(document.status());
  absl::StatusOr<formats::FbxTakeRig> rig = formats::ReadFbxTakeRig(*document, request.fbx_take());
  if (!rig.ok()) {
    const bool take = rig.status().message().rfind("take \"", 0) == 0;
    return take ? absl::Status(rig.status().code(),
                               absl::StrCat("fbx_take: ", rig.status().message()))
                : InFbx(rig.status());
  }
  const formats::FbxTakeInfo& take = rig->take;
  const double seconds = static_cast<double>(take.stop - take.start) / kFbxTicksPerSecond;
  if (!(seconds >= 0) || !std::isfinite(seconds)) {
    return absl::InvalidArgumentError(absl::StrCat("fbx: take \"", take.name, "\" stops (",
                                                   take.stop, ") before it starts (", take.start,
                                                   ")"));
  }
  const int64_t joints = static_cast<int64_t>(rig->names.size());
  const double frames_exact = std::floor(seconds * rig->fps + 1e-6) + 1;
  if (joints == 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "fbx: take \"", take.name, "\" moves no model, and the file has no bones or Nulls"));
  }
  if (frames_exact > static_cast<double>(limits.max_values) / static_cast<double>(joints * 3)) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "fbx: take \"", take.name, "\": ", frames_exact, " frames at ", rig->fps, " fps x ", joints,
        " models x 3 exceeds the server limit --max_values=", limits.max_values));
  }
  const auto frames = static_cast<int64_t>(frames_exact);
  if (frames < 2) {
    return absl::InvalidArgumentError(absl::StrCat("fbx: take \"", take.name, "\" is ", frames,
                                                   " frame long at ", rig->fps,
                                                   " fps: nothing to retime"));
  }
  v1::RetimeSkeletalRequest decoded;
  decoded.CopyFrom(request);
  decoded.clear_fbx();
  decoded.clear_fbx_take();
  decoded.set_return_motion(false);
  *decoded.mutable_motion() = convert::FbxMotion(*rig, frames);
  KOMA_RETURN_IF_ERROR(StopReason());  // a stopped evaluation left positions unfinished
  KOMA_RETURN_IF_ERROR(GrowCallReservation(
      FileOverheadFootprint(static_cast<int64_t>(bytes.size()), formats::FormatId::kFbx) +
          ExpectedFootprint(decoded, static_cast<int64_t>(bytes.size()), limits),
      "this FBX request (the parsed file, the sampled models, work, response)"));
  KOMA_RETURN_IF_ERROR(HandleRetimeSkeletal(decoded, limits, response));
  const double output_fps = response->timing_fps() > 0 && request.output_rate() == v1::TIMING_RATE
                                ? response->timing_fps()
                                : rig->fps;
  v1::FbxTakeTiming* info = response->mutable_fbx_take();
  info->set_name(take.name);
  info->set_source_fps(rig->fps);
  info->set_start_s(static_cast<double>(take.start) / kFbxTicksPerSecond);
  info->set_frame_count(static_cast<int32_t>(frames));
  for (const std::string& name : rig->names) info->add_joints(name);
  info->set_output_fps(output_fps);
  info->set_layers(take.layers);
  if (take.layers > 1) {
    response->add_warnings(absl::StrCat(
        "fbx: take \"", take.name, "\" has ", take.layers,
        " animation layers; koma read and retimed the base layer only (merge the layers in the "
        "DCC first to retime them all)"));
  }
  if (described != nullptr) {
    described->frames = static_cast<int>(frames);
    described->joints = static_cast<int>(joints);
    described->warnings.assign(response->warnings().begin(), response->warnings().end());
  }
  const bool return_motion = !request.has_return_motion() || request.return_motion();
  if (!return_motion) return absl::OkStatus();
  std::vector<int64_t> ticks(static_cast<size_t>(response->source_frames_size()));
  for (size_t k = 0; k < ticks.size(); ++k) {
    ticks[k] = take.start +
               std::llround(static_cast<double>(response->source_frames(static_cast<int>(k))) *
                            static_cast<double>(kFbxTicksPerSecond) / rig->fps);
  }
  absl::StatusOr<std::string> written =
      formats::WriteFbxRetimed(*std::move(document), *rig, ticks, output_fps);
  if (!written.ok()) return InFbx(written.status());
  info->set_curves_written(static_cast<int32_t>(rig->curve_ids.size()));
  response->set_fbx(*std::move(written));
  return absl::OkStatus();
}

}  // namespace koma::server

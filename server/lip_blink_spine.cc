#include "server/lip_blink_spine.h"

#include <string>
#include <utility>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "convert/spine_lip_blink.h"
#include "core/status_macros.h"
#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "server/file_requests.h"
#include "server/lip_blink_request.h"

namespace koma::server {
namespace {

absl::Status NotWithSpine(absl::string_view field, absl::string_view value,
                          absl::string_view reason) {
  return absl::InvalidArgumentError(
      absl::StrCat(field, ": ", value, " is not for spine_json (", reason, ")"));
}

// The fields spine_json decides itself.
absl::Status CheckSpineFields(const v1::LipBlinkRequest& request) {
  if (!request.mouth().ids().empty()) {
    return NotWithSpine("mouth.ids", request.mouth().ids(0), "the mouth is spine.mouth_slot");
  }
  if (!request.eyes().ids().empty()) {
    return NotWithSpine("eyes.ids", request.eyes().ids(0), "the eyes are spine.eye_slots");
  }
  constexpr const char* kLevels = "the drawings' levels are 0 and 1";
  if (request.mouth().has_min()) {
    return NotWithSpine("mouth.min", absl::StrCat(request.mouth().min()), kLevels);
  }
  if (request.mouth().has_max()) {
    return NotWithSpine("mouth.max", absl::StrCat(request.mouth().max()), kLevels);
  }
  if (request.eyes().has_min()) {
    return NotWithSpine("eyes.min", absl::StrCat(request.eyes().min()), kLevels);
  }
  if (request.eyes().has_max()) {
    return NotWithSpine("eyes.max", absl::StrCat(request.eyes().max()), kLevels);
  }
  constexpr const char* kFps = "the skeleton's fps is the motion's";
  if (request.voice_motion_fps() != 0) {
    return NotWithSpine("voice_motion_fps", absl::StrCat(request.voice_motion_fps()), kFps);
  }
  if (request.voice_output() != v1::LIP_BLINK_VOICE_OUTPUT_UNSPECIFIED) {
    return NotWithSpine("voice_output", v1::LipBlinkVoiceOutput_Name(request.voice_output()),
                        "the answer's file is spine_json");
  }
  if (request.csv_fps() != 0) {
    return NotWithSpine("csv_fps", absl::StrCat(request.csv_fps()), kFps);
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status HandleLipBlinkSpine(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                 v1::LipBlinkResponse* response, LipBlinkMotionShape* shape) {
  KOMA_RETURN_IF_ERROR(CheckSpineFields(request));
  KOMA_RETURN_IF_ERROR(CheckLipBlinkFileSize(request.spine_json(), "spine_json", limits));
  absl::StatusOr<formats::SpineFile> file = formats::ParseSpine(request.spine_json());
  if (!file.ok()) {
    return absl::Status(file.status().code(),
                        absl::StrCat("spine_json: ", file.status().message()));
  }
  const bool has_voice = request.voice_case() != v1::LipBlinkRequest::VOICE_NOT_SET;
  KOMA_ASSIGN_OR_RETURN(
      const convert::SpineLipBlinkSlots slots,
      convert::SpineLipBlinkSlotsOf(request.spine(), *file, has_voice,
                                    !request.mouth().speech().empty(),
                                    convert::ProtoSpineLipBlinkNames()));
  absl::StatusOr<v1::LipBlinkRequest> decoded =
      convert::DecodedSpineLipBlinkRequest(request, *file, slots);
  if (!decoded.ok()) {  // the animation's eye keys: their JSON path
    return absl::Status(decoded.status().code(),
                        absl::StrCat("spine_json: ", decoded.status().message()));
  }
  KOMA_RETURN_IF_ERROR(ReserveDecodedLipBlink(*decoded, request.spine_json().size(), limits));
  if (absl::Status s = HandleLipBlink(*decoded, limits, response, shape); !s.ok()) {
    // The decoded request's curves are the slots: say so ("spine_json: the slots as curves:
    // 2 curves x ... frames exceeds the server limit --max_values=...").
    if (absl::StartsWith(s.message(), "curves")) {
      return absl::Status(s.code(), absl::StrCat("spine_json: the slots as ", s.message()));
    }
    return s;
  }
  KOMA_ASSIGN_OR_RETURN(const std::vector<formats::SpineAttachmentTimeline> timelines,
                        convert::SpineTimelinesOf(*file, slots, *response));
  absl::StatusOr<std::string> text =
      formats::WriteSpineAttachments(*file, slots.animation, timelines);
  if (!text.ok()) return absl::InternalError(text.status().message());
  response->set_spine_json(*std::move(text));  // replaces a voice motion's motion3_json
  response->set_spine_new_animation(!slots.existing);
  return absl::OkStatus();
}

}  // namespace koma::server

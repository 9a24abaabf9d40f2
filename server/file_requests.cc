#include "server/file_requests.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "convert/curves_convert.h"
#include "convert/skeletal_convert.h"
#include "core/status_macros.h"
#include "formats/bvh.h"
#include "server/call_footprint.h"
#include "server/call_reservation.h"
#include "server/fbx_request.h"
#include "server/gltf_request.h"
#include "server/lip_blink_request.h"
#include "server/response_slice.h"

namespace koma::server {
namespace {

// The CLI's default for `--fps` of a CSV input.
constexpr double kDefaultCsvFps = 30.0;

absl::Status CheckFileSize(const std::string& text, absl::string_view field,
                           const RequestLimits& limits) {
  if (static_cast<int64_t>(text.size()) <= limits.max_file_bytes) return absl::OkStatus();
  return absl::ResourceExhaustedError(absl::StrCat(field, ": ", text.size(),
                                                   " bytes exceeds the server limit "
                                                   "--max_file_bytes=",
                                                   limits.max_file_bytes));
}

// The written file in the response field of its format: csv_text or motion3_json.
template <typename Response>
void PutCurveText(bool csv, std::string text, Response* response) {
  if (csv) {
    response->set_csv_text(std::move(text));
  } else {
    response->set_motion3_json(std::move(text));
  }
}

// The same for RetimeCurves, whose file may also be a Spine skeleton.
void PutCurveText(const CurveFile& file, std::string text, v1::RetimeCurvesResponse* response) {
  if (file.input.spine && !file.csv) {
    response->set_spine_json(std::move(text));
  } else {
    PutCurveText(file.csv, std::move(text), response);
  }
}

// A reader's error with the request field in front: "bvh_text: line 12: ...".
absl::Status InField(const absl::Status& status, absl::string_view field) {
  return absl::Status(status.code(), absl::StrCat(field, ": ", status.message()));
}

// Unset or 0: the CLI's 30; else finite and > 0.
absl::StatusOr<double> CsvFps(double csv_fps) {
  if (csv_fps == 0) return kDefaultCsvFps;
  if (!std::isfinite(csv_fps) || csv_fps < 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "csv_fps: ", csv_fps, " must be finite and > 0 (frames per second of csv_text; 0: 30)"));
  }
  return csv_fps;
}

// The motion3_json or csv_text of a RetimeCurves or LipBlink request, parsed.
template <typename Request>
absl::StatusOr<CurveFile> ParseCurveFile(const Request& request, const RequestLimits& limits) {
  const bool csv = request.input_case() == Request::kCsvText;
  const std::string& text = csv ? request.csv_text() : request.motion3_json();
  const absl::string_view field = csv ? "csv_text" : "motion3_json";
  KOMA_RETURN_IF_ERROR(CheckFileSize(text, field, limits));
  double fps = kDefaultCsvFps;
  if (csv) {
    KOMA_ASSIGN_OR_RETURN(fps, CsvFps(request.csv_fps()));
  }
  absl::StatusOr<convert::CurveInput> input = convert::ParseCurveText(text, csv, fps);
  if (!input.ok()) return InField(input.status(), field);
  return CurveFile{*std::move(input), csv};
}

// The spine_json of a RetimeCurves request, parsed, with spine_animation's curves.
absl::StatusOr<CurveFile> ParseSpineFile(const v1::RetimeCurvesRequest& request,
                                         const RequestLimits& limits) {
  KOMA_RETURN_IF_ERROR(CheckFileSize(request.spine_json(), "spine_json", limits));
  absl::StatusOr<formats::SpineFile> spine = formats::ParseSpine(request.spine_json());
  if (!spine.ok()) return InField(spine.status(), "spine_json");
  absl::StatusOr<convert::CurveInput> input =
      convert::SpineCurveInput(*std::move(spine), request.spine_animation());
  if (!input.ok()) {
    return InField(absl::InvalidArgumentError(input.status().message()), "spine_animation");
  }
  return CurveFile{*std::move(input), false};
}

// The request with the file's curves in place of the file (every other field kept).
template <typename Request>
void Decode(const Request& request, const CurveFile& file, Request* decoded) {
  decoded->CopyFrom(request);
  *decoded->mutable_curves() = convert::CurveSetToProto(file.input.curves);  // drops the text
  decoded->clear_csv_fps();
}

void Decode(const v1::RetimeCurvesRequest& request, const CurveFile& file,
            v1::RetimeCurvesRequest* decoded) {
  Decode<v1::RetimeCurvesRequest>(request, file, decoded);
  decoded->clear_spine_animation();
}

constexpr char kParsedFile[] =
    "this file request (the parsed file, the decoded request, work, response)";

// Once the file is parsed its call's size is known: the memory budget's reservation grows
// from the text's estimate to the decoded request's footprint plus the file's own
// (server/call_footprint.h); RESOURCE_EXHAUSTED naming the budget when that does not fit.
template <typename Request>
absl::Status ReserveDecoded(const Request& decoded, size_t file_bytes, formats::FormatId kind,
                            const RequestLimits& limits) {
  const auto bytes = static_cast<int64_t>(file_bytes);
  return GrowCallReservation(
      FileOverheadFootprint(bytes, kind) + ExpectedFootprint(decoded, bytes, limits), kParsedFile);
}

// The size of a RetimeCurves or LipBlink request's file.
template <typename Request>
size_t CurveFileBytes(const Request& request) {
  return request.input_case() == Request::kCsvText ? request.csv_text().size()
                                                   : request.motion3_json().size();
}

size_t CurveFileBytes(const v1::RetimeCurvesRequest& request) {
  if (request.input_case() == v1::RetimeCurvesRequest::kSpineJson) {
    return request.spine_json().size();
  }
  return CurveFileBytes<v1::RetimeCurvesRequest>(request);
}

// `message` (one field set) serialised.
template <typename Message>
absl::StatusOr<std::string> Serialised(const Message& message) {
  std::string bytes;
  if (!message.SerializeToString(&bytes)) {
    return absl::InternalError("response: the file field cannot be serialised");
  }
  return bytes;
}

}  // namespace

bool CarriesFile(const v1::RetimeSkeletalRequest& request) {
  return request.input_case() == v1::RetimeSkeletalRequest::kBvhText ||
         request.input_case() == v1::RetimeSkeletalRequest::kGltf ||
         request.input_case() == v1::RetimeSkeletalRequest::kFbx;
}
bool CarriesFile(const v1::RetimeCurvesRequest& request) {
  return request.input_case() == v1::RetimeCurvesRequest::kMotion3Json ||
         request.input_case() == v1::RetimeCurvesRequest::kCsvText ||
         request.input_case() == v1::RetimeCurvesRequest::kSpineJson;
}
bool CarriesFile(const v1::LipBlinkRequest& request) {
  return request.input_case() == v1::LipBlinkRequest::kMotion3Json ||
         request.input_case() == v1::LipBlinkRequest::kCsvText;
}

absl::Status HandleRetimeSkeletalFile(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits,
                                      v1::RetimeSkeletalResponse* response,
                                      SkeletalAnswer* described) {
  if (request.input_case() == v1::RetimeSkeletalRequest::kGltf) {
    return HandleRetimeSkeletalGltf(request, limits, response, described);
  }
  if (request.input_case() == v1::RetimeSkeletalRequest::kFbx) {
    return HandleRetimeSkeletalFbx(request, limits, response, described);
  }
  KOMA_RETURN_IF_ERROR(CheckFileSize(request.bvh_text(), "bvh_text", limits));
  std::vector<std::string> warnings;
  absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(request.bvh_text(), &warnings);
  if (!clip.ok()) return InField(clip.status(), "bvh_text");
  for (std::string& warning : warnings) warning.insert(0, "bvh_text: ");
  if (described != nullptr) {
    described->frames = clip->frame_count;
    described->joints = static_cast<int>(clip->skeleton.joints.size());
    described->warnings = warnings;
  }
  {
    v1::RetimeSkeletalRequest decoded;
    decoded.CopyFrom(request);
    *decoded.mutable_motion() = convert::ToProto(*clip);  // drops the text
    // The frames now live in `decoded` only (the writer needs just the skeleton): a file near
    // --max_file_bytes decodes to tens of MB, held once here, not twice.
    std::vector<double>().swap(clip->values);
    KOMA_RETURN_IF_ERROR(
        ReserveDecoded(decoded, request.bvh_text().size(), formats::FormatId::kBvh, limits));
    KOMA_RETURN_IF_ERROR(HandleRetimeSkeletal(decoded, limits, response));
  }  // `decoded` freed before the retimed clip and its text are built
  for (std::string& warning : warnings) response->add_warnings(std::move(warning));
  if (!response->has_motion()) return absl::OkStatus();  // return_motion false
  // The CLI's steps exactly: the retimed clip from the response, on the parsed skeleton.
  absl::StatusOr<SkeletalClip> retimed = convert::ClipFromResponse(*response, clip->skeleton);
  if (!retimed.ok()) return absl::InternalError(retimed.status().message());
  response->clear_motion();
  response->set_bvh_text(formats::WriteBvh(*retimed));
  return absl::OkStatus();
}

absl::Status RetimeSkeletalFileAnswer(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits, SkeletalAnswer* answer) {
  v1::RetimeSkeletalResponse response;
  KOMA_RETURN_IF_ERROR(HandleRetimeSkeletalFile(request, limits, &response, answer));
  const size_t size = response.ByteSizeLong();
  if (size > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "response: ", size, " bytes is over protobuf's 2 GiB message limit; send fewer frames"));
  }
  answer->bytes = UninitialisedSlice(size);
  response.SerializeWithCachedSizesToArray(const_cast<uint8_t*>(answer->bytes.begin()));
  return absl::OkStatus();
}

absl::Status DecodeCurvesFile(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                              v1::RetimeCurvesRequest* decoded, CurveFile* file) {
  if (request.input_case() == v1::RetimeCurvesRequest::kSpineJson) {
    KOMA_ASSIGN_OR_RETURN(*file, ParseSpineFile(request, limits));
  } else {
    KOMA_ASSIGN_OR_RETURN(*file, ParseCurveFile(request, limits));
  }
  Decode(request, *file, decoded);
  return ReserveDecoded(*decoded, CurveFileBytes(request), CurveFileKind(request), limits);
}

absl::StatusOr<std::string> CurvesFileField(
    const CurveFile& file, std::vector<std::optional<convert::CurveReplacement>> retimed) {
  absl::StatusOr<std::string> text = convert::CurveOutputText(file.input, retimed, file.csv);
  if (!text.ok()) return absl::InternalError(text.status().message());
  v1::RetimeCurvesResponse field;
  PutCurveText(file, *std::move(text), &field);
  return Serialised(field);
}

absl::StatusOr<CurveFile> ParseLipBlinkFile(const v1::LipBlinkRequest& request,
                                            const RequestLimits& limits) {
  return ParseCurveFile(request, limits);
}

absl::Status CheckLipBlinkFileSize(const std::string& bytes, absl::string_view field,
                                   const RequestLimits& limits) {
  return CheckFileSize(bytes, field, limits);
}

absl::Status HandleLipBlinkFile(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                v1::LipBlinkResponse* response, LipBlinkMotionShape* shape) {
  KOMA_ASSIGN_OR_RETURN(const CurveFile file, ParseCurveFile(request, limits));
  v1::LipBlinkRequest decoded;
  Decode(request, file, &decoded);
  KOMA_RETURN_IF_ERROR(
      ReserveDecoded(decoded, CurveFileBytes(request), CurveFileKind(request), limits));
  KOMA_RETURN_IF_ERROR(HandleLipBlink(decoded, limits, response, shape));
  return PutLipBlinkFile(file, response);
}

absl::Status ReserveDecodedLipBlink(const v1::LipBlinkRequest& decoded, size_t file_bytes,
                                    const RequestLimits& limits) {
  return ReserveDecoded(decoded, file_bytes, formats::FormatId::kSpine, limits);
}

absl::Status PutLipBlinkFile(const CurveFile& file, v1::LipBlinkResponse* response) {
  // As `koma lipblink` writes its output: the converted curves replace theirs by id.
  const std::vector<Curve>& curves = file.input.curves.curves;
  std::vector<std::optional<convert::CurveReplacement>> replacements(curves.size());
  for (const v1::ConvertedCurve& converted : response->curves()) {
    for (size_t i = 0; i < curves.size(); ++i) {
      if (curves[i].id != converted.id()) continue;
      replacements[i] = convert::ReplacementFromProto(converted);
      break;
    }
  }
  absl::StatusOr<std::string> text = convert::CurveOutputText(file.input, replacements, file.csv);
  if (!text.ok()) return absl::InternalError(text.status().message());
  PutCurveText(file.csv, *std::move(text), response);
  return absl::OkStatus();
}

}  // namespace koma::server

// Requests that carry a file (RetimeSkeletalRequest.bvh_text, RetimeCurvesRequest and
// LipBlinkRequest .motion3_json / .csv_text) instead of the decoded motion.
//
// The server parses the file with the readers of the `koma` CLI (formats/), turns it into the
// decoded request the CLI would have sent (convert/), answers that through the ordinary path,
// and writes the retimed file with the CLI's writers from the same answer. So a file request's
// timing fields are those of the decoded request, and its file is byte for byte the CLI's
// output for the same input and options.
//
// Errors: RESOURCE_EXHAUSTED when the file is over RequestLimits::max_file_bytes, and the
// readers' own errors (INVALID_ARGUMENT with the line, or the JSON path) prefixed with the
// field: "bvh_text: line 12: unknown channel name ...". What the file decodes to is then
// validated as a decoded request is (max_values, max_joints, frame_count >= 2, ...).
#ifndef KOMA_SERVER_FILE_REQUESTS_H_
#define KOMA_SERVER_FILE_REQUESTS_H_

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "convert/curve_text.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"
#include "server/skeletal_request.h"

namespace koma::server {

// The file a RetimeCurves or LipBlink request carried, parsed, kept to write the answer's file.
struct CurveFile {
  convert::CurveInput input;
  bool csv = false;  // csv_text (else motion3_json)
};

// True when the request carries a file rather than decoded motion.
bool CarriesFile(const v1::RetimeSkeletalRequest& request);
bool CarriesFile(const v1::RetimeCurvesRequest& request);
bool CarriesFile(const v1::LipBlinkRequest& request);

// RetimeSkeletal with bvh_text: the answer's bytes are a RetimeSkeletalResponse with the
// retimed BVH in bvh_text and no motion (none either when return_motion is false). The file's
// frame and joint counts go to `described` when given (for the call's log line and metrics).
absl::Status HandleRetimeSkeletalFile(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits,
                                      v1::RetimeSkeletalResponse* response,
                                      SkeletalAnswer* described = nullptr);
absl::Status RetimeSkeletalFileAnswer(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits, SkeletalAnswer* answer);

// RetimeCurves with a file: the decoded request it stands for (the request's options, the
// file's curves) into `decoded`, the parsed file into `file`.
absl::Status DecodeCurvesFile(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                              v1::RetimeCurvesRequest* decoded, CurveFile* file);

// The RetimeCurvesResponse field holding the retimed file (motion3_json or csv_text),
// serialised: what follows the response's other fields on the wire. `retimed[c]` is curve c's
// retimed per-frame values and stepped keyframes, every curve of the file retimed.
absl::StatusOr<std::string> CurvesFileField(
    const CurveFile& file, std::vector<std::optional<convert::CurveReplacement>> retimed);

// LipBlink with a file: the decoded request answered by HandleLipBlink, plus the file.
struct LipBlinkMotionShape;  // server/lip_blink_request.h
absl::Status HandleLipBlinkFile(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                v1::LipBlinkResponse* response, LipBlinkMotionShape* shape);

// The parts a voice request (server/lip_blink_voice.h) shares: the request's motion file
// parsed (with the size limit), the size limit for another field, and the converted file
// written into `response` (csv_text or motion3_json, the response's curves replacing theirs by
// id, every other curve kept).
absl::StatusOr<CurveFile> ParseLipBlinkFile(const v1::LipBlinkRequest& request,
                                             const RequestLimits& limits);
absl::Status CheckLipBlinkFileSize(const std::string& bytes, absl::string_view field,
                                   const RequestLimits& limits);
absl::Status PutLipBlinkFile(const CurveFile& file, v1::LipBlinkResponse* response);

// The memory budget's reservation for a parsed file's decoded LipBlink request (a Spine
// skeleton's, server/lip_blink_spine.h): as for the other files, RESOURCE_EXHAUSTED naming the
// budget when it does not fit.
absl::Status ReserveDecodedLipBlink(const v1::LipBlinkRequest& decoded, size_t file_bytes,
                                    const RequestLimits& limits);

}  // namespace koma::server

#endif  // KOMA_SERVER_FILE_REQUESTS_H_

// What one Retime call is expected to hold in memory, for the server's memory budget
// (server/memory_budget.h). Estimates from the request's sizes, upper bounds for the
// arrays koma allocates; checked against measured peaks in tests/e2e/memory_budget_test.sh.
#ifndef KOMA_SERVER_CALL_FOOTPRINT_H_
#define KOMA_SERVER_CALL_FOOTPRINT_H_

#include <cstdint>
#include <string_view>

#include "formats/format_table.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// Before the request is parsed: its received bytes, and the parsed copy that exists beside
// them until they are freed (about as large: the big arrays are packed doubles either way).
int64_t ReceivedFootprint(int64_t request_bytes);

// Once parsed: the request message, the working arrays and the response. The request's
// counts (frames, joints, curves) are not validated yet; they are capped by --max_values,
// beyond which validation refuses the call anyway, so a request that only claims to be
// huge is refused by validation with its field named, not by the budget.
//   RetimeSkeletal: values + forward kinematics' world positions (frames x joints x 3) + the
//                   returned motion (as large as the values) + per-frame arrays;
//   RetimeCurves, LipBlink: the request + each curve's per-frame values twice (the result,
//                   and the response it is encoded into) + per-frame arrays.
int64_t ExpectedFootprint(const v1::RetimeSkeletalRequest& request, int64_t request_bytes,
                          const RequestLimits& limits);
int64_t ExpectedFootprint(const v1::RetimeCurvesRequest& request, int64_t request_bytes,
                          const RequestLimits& limits);
int64_t ExpectedFootprint(const v1::LipBlinkRequest& request, int64_t request_bytes,
                          const RequestLimits& limits);

// A request carrying a file (server/file_requests.h) is sized by the file until it is parsed:
// the bytes and what parsing builds (BVH: the numbers, ~1x the text; the JSON formats: a
// document of several times the text; glTF: the JSON document and tinygltf's model, tens of
// times its JSON, beside its binary buffers). Once parsed, the handler grows the call's
// reservation to FileOverheadFootprint plus the decoded request's ExpectedFootprint. The
// factors are upper bounds of the peaks bench/format_memory.py measures on the real server
// (docs/reliability.md, "Memory per format"), kept in the format's row of the format table
// (formats/format_table.h: parse_bytes_per_byte, kept_bytes_per_byte).
int64_t FileParseFootprint(int64_t file_bytes, formats::FormatId format);
// Beside the decoded request's footprint, until the answer is written: the text, the parsed
// file (the JSON documents are kept to write the answer back) and the retimed file's text.
int64_t FileOverheadFootprint(int64_t file_bytes, formats::FormatId format);
// A glTF file's (GLB or .gltf text): its bytes plus its JSON's document and tinygltf's model,
// counted on the JSON without its data URIs and long strings (a GLB's JSON chunk).
int64_t GltfFootprint(std::string_view file);
// The format of a RetimeCurves or LipBlink request's file: the format table's row of its
// `input` field (motion3.json when it has none).
formats::FormatId CurveFileKind(const v1::RetimeCurvesRequest& request);
formats::FormatId CurveFileKind(const v1::LipBlinkRequest& request);

}  // namespace koma::server

#endif  // KOMA_SERVER_CALL_FOOTPRINT_H_

// What one Retime call is expected to hold in memory, for the server's memory budget
// (server/memory_budget.h). Estimates from the request's sizes, upper bounds for the
// arrays koma allocates; checked against measured peaks in tests/e2e/memory_budget_test.sh.
#ifndef KOMA_SERVER_CALL_FOOTPRINT_H_
#define KOMA_SERVER_CALL_FOOTPRINT_H_

#include <cstdint>

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

// A request carrying a file (bvh_text, motion3_json, csv_text; server/file_requests.h) is sized
// by its text until it is parsed: the text and what parsing builds (BVH: the numbers, ~1x the
// text; motion3.json's JSON document and CSV rows: several times the text). Once parsed, the
// file handler grows the call's reservation to FileOverheadFootprint plus the decoded
// request's ExpectedFootprint. The factors are measured peaks (docs/python.md, "Memory"):
// a 28.6 MB BVH peaked 142 MB above the idle server, an 8.1 MB motion3.json (40 curves x 6,000
// linear keys) 100 MB, a 2 MB CSV 24 MB.
int64_t FileParseFootprint(int64_t file_bytes, bool bvh);
// Beside the decoded request's footprint, until the answer is written: the text, the parsed
// file (the motion3 document is kept to write the answer back) and the retimed file's text.
int64_t FileOverheadFootprint(int64_t file_bytes, bool bvh);

}  // namespace koma::server

#endif  // KOMA_SERVER_CALL_FOOTPRINT_H_

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

}  // namespace koma::server

#endif  // KOMA_SERVER_CALL_FOOTPRINT_H_

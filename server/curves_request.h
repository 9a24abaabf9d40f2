// RetimeCurves: proto request -> validated core inputs -> koma-uchi -> proto response.
#ifndef KOMA_SERVER_CURVES_REQUEST_H_
#define KOMA_SERVER_CURVES_REQUEST_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_lip_blink.h"
#include "server/file_requests.h"
#include "server/request_limits.h"

namespace koma::server {

struct CurvesJob {
  CurveSet set;
  KomaUchiOptions options;
  std::vector<GroupLipBlink> lip_blinks;  // the GROUP_LIP_BLINK groups' LipBlink drawings
};

// Every field checked before any work; INVALID_ARGUMENT / RESOURCE_EXHAUSTED naming the
// field path and value.
absl::StatusOr<CurvesJob> ValidateCurvesRequest(const v1::RetimeCurvesRequest& request,
                                                const RequestLimits& limits);

// What a RetimeCurves call answers, before it is put in a response: the request's curves
// (their ids name the answer's curves) and options, and the core's result for them.
// A request that carried a file (motion3_json, csv_text) also keeps the parsed file until the
// retiming is done, and its answer ends with the retimed file (server/file_requests.h).
struct CurvesAnswer {
  CurveSet set;
  KomaUchiOptions options;
  std::vector<GroupLipBlink> lip_blinks;
  KomaUchiResult result;
  std::unique_ptr<CurveFile> file;  // null for a decoded request
  std::string file_field;           // the response's serialised file field; empty: none
};

// Validates `request` into the answer's set and options: everything the call reads of the
// request, so the service can free the request (~30 MB of messages at 500 curves x 10k
// frames) before the retiming builds the result.
absl::Status PrepareCurvesAnswer(const v1::RetimeCurvesRequest& request,
                                 const RequestLimits& limits, CurvesAnswer* answer);

// Retimes a prepared answer into its result (OUT_OF_RANGE when a curve evaluates to inf or
// NaN). The service encodes the answer's wire bytes itself (server/curves_response.h).
absl::Status CompleteCurvesAnswer(CurvesAnswer* answer);

// PrepareCurvesAnswer then CompleteCurvesAnswer.
absl::Status RetimeCurvesAnswer(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                                CurvesAnswer* answer);

// The answer as a RetimeCurvesResponse message: the reference the wire encoder is tested
// against, and the response of the typed-API benchmark servers.
void FillCurvesResponse(const CurveSet& set, const KomaUchiResult& result,
                        v1::RetimeCurvesResponse* response);

// RetimeCurvesAnswer then FillCurvesResponse.
absl::Status HandleRetimeCurves(const v1::RetimeCurvesRequest& request, const RequestLimits& limits,
                                v1::RetimeCurvesResponse* response);

}  // namespace koma::server

#endif  // KOMA_SERVER_CURVES_REQUEST_H_

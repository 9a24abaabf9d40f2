// RetimeCurves: proto request -> validated core inputs -> koma-uchi -> proto response.
#ifndef KOMA_SERVER_CURVES_REQUEST_H_
#define KOMA_SERVER_CURVES_REQUEST_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

struct CurvesJob {
  CurveSet set;
  KomaUchiOptions options;
};

// Every field checked before any work; INVALID_ARGUMENT / RESOURCE_EXHAUSTED naming the
// field path and value.
absl::StatusOr<CurvesJob> ValidateCurvesRequest(const v1::RetimeCurvesRequest& request,
                                                const RequestLimits& limits);

absl::Status HandleRetimeCurves(const v1::RetimeCurvesRequest& request,
                                const RequestLimits& limits, v1::RetimeCurvesResponse* response);

}  // namespace koma::server

#endif  // KOMA_SERVER_CURVES_REQUEST_H_

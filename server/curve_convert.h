// The server's checks around the curve conversion (convert/curves_convert.h), shared by
// RetimeCurves and LipBlink: the size limit before converting, finite values after evaluating.
#ifndef KOMA_SERVER_CURVE_CONVERT_H_
#define KOMA_SERVER_CURVE_CONVERT_H_

#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "core/curves.h"
#include "koma/v1/motion.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// Converts and validates (convert::CurveSetFromProto, core ValidateCurveSet) a request's
// curve set. Errors name the field under `path` ("curves"): INVALID_ARGUMENT for malformed
// curves, RESOURCE_EXHAUSTED when curves x frames or the number of points is over
// --max_values (checked first, before anything is copied).
absl::StatusOr<CurveSet> CurveSetFromProto(const v1::CurveSet& proto, absl::string_view path,
                                           const RequestLimits& limits);

// OUT_OF_RANGE when curves.curves[curve_index] evaluated to inf or NaN somewhere: finite
// keys can still overflow (a linear segment from -1e308 to 1e308), and such a curve must get
// an error, never a silent NaN in an answer.
absl::Status CheckEvaluatedFinite(const std::vector<double>& values, int curve_index);

}  // namespace koma::server

#endif  // KOMA_SERVER_CURVE_CONVERT_H_

#include "server/curve_convert.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "convert/curves_convert.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"

namespace koma::server {
namespace {

absl::Status CheckSize(const v1::CurveSet& proto, absl::string_view path,
                       const RequestLimits& limits) {
  int64_t points = 0;
  for (const v1::Curve& curve : proto.curves()) {
    points += curve.samples_size() + 1 + 3LL * curve.segments_size();
  }
  const int64_t frame_values =
      static_cast<int64_t>(proto.curves_size()) * std::max<int64_t>(proto.frame_count(), 0);
  const int64_t work = std::max(points, frame_values);
  if (work > limits.max_values) {
    return absl::ResourceExhaustedError(absl::StrCat(
        path, ": ", proto.curves_size(), " curves x ", proto.frame_count(), " frames (", points,
        " points) exceeds the server limit --max_values=", limits.max_values));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<CurveSet> CurveSetFromProto(const v1::CurveSet& proto, absl::string_view path,
                                           const RequestLimits& limits) {
  KOMA_RETURN_IF_ERROR(CheckSize(proto, path, limits));
  return convert::CurveSetFromProto(proto, path);
}

absl::Status CheckEvaluatedFinite(const std::vector<double>& values, int curve_index) {
  if (AllFinite(values)) return absl::OkStatus();  // one vectorised pass; the loop names the frame
  for (size_t f = 0; f < values.size(); ++f) {
    if (!std::isfinite(values[f])) {
      return absl::OutOfRangeError(absl::StrCat("curves.curves[", curve_index, "]: evaluates to ",
                                                values[f], " at frame ", f,
                                                " (values too large to interpolate)"));
    }
  }
  return absl::OkStatus();
}

}  // namespace koma::server

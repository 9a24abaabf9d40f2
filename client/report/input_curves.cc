#include "client/report/input_curves.h"

#include "absl/strings/str_cat.h"
#include "convert/curves_convert.h"
#include "core/curves.h"

namespace koma::client::report {

std::vector<double> SampleInputCurve(const v1::CurveSet& set, int index) {
  const absl::StatusOr<Curve> curve =
      convert::CurveFromProto(set.curves(index), absl::StrCat("curves.curves[", index, "]"));
  // The server took this request, so its curves convert; a hand-made request with a
  // malformed curve (which the server would refuse) draws no "before" line.
  if (!curve.ok()) return {};
  return SampleEveryFrame(*curve, set.frame_count(), set.beziers_restricted());
}

}  // namespace koma::client::report

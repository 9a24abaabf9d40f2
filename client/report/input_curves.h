// The request's curves as the reports plot them ("before"): converted as the server converts
// them (convert/curves_convert.h) and sampled at every frame with motion3.json's rules
// (core/curves.h).
#ifndef KOMA_CLIENT_REPORT_INPUT_CURVES_H_
#define KOMA_CLIENT_REPORT_INPUT_CURVES_H_

#include <vector>

#include "koma/v1/motion.pb.h"

namespace koma::client::report {

// Curve `index` of `set` at frames 0 .. frame_count - 1; empty for a curve the server would
// refuse (CurveFromProto's errors).
std::vector<double> SampleInputCurve(const v1::CurveSet& set, int index);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_INPUT_CURVES_H_

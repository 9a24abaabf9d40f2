// CurveSet (formats/ side) <-> koma.v1 curve messages (wire side), for the CLI and for the
// server's file-carrying requests.
#ifndef KOMA_CONVERT_CURVES_CONVERT_H_
#define KOMA_CONVERT_CURVES_CONVERT_H_

#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/motion.pb.h"
#include "koma/v1/retime.pb.h"

namespace koma::convert {

v1::CurveSet CurveSetToProto(const CurveSet& set);

// A response curve's stepped keyframes as points (start, then each segment's end).
std::vector<CurvePoint> StepsFromProto(const v1::Curve& stepped);

// A response timing as the core type (for the drawing sheet writer).
DrawingTiming TimingFromProto(const v1::DrawingTiming& timing);

// "closed", "mid" or "open" for a MouthShape (the CLI's summaries and the report's strip);
// "unspecified" for any other value.
const char* MouthShapeName(int shape);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_CURVES_CONVERT_H_

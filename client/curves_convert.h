// CurveSet (formats/ side) <-> koma.v1 curve messages (wire side) for the CLI.
#ifndef KOMA_CLIENT_CURVES_CONVERT_H_
#define KOMA_CLIENT_CURVES_CONVERT_H_

#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"
#include "koma/v1/motion.pb.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

v1::CurveSet CurveSetToProto(const CurveSet& set);

// A response curve's stepped keyframes as points (start, then each segment's end).
std::vector<CurvePoint> StepsFromProto(const v1::Curve& stepped);

// A response timing as the core type (for the drawing sheet writer).
DrawingTiming TimingFromProto(const v1::DrawingTiming& timing);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CURVES_CONVERT_H_

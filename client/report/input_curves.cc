#include "client/report/input_curves.h"

#include "core/curves.h"

namespace koma::client::report {
namespace {

SegmentType TypeFromProto(int type) {
  switch (type) {
    case v1::SEGMENT_BEZIER:
      return SegmentType::kBezier;
    case v1::SEGMENT_STEPPED:
      return SegmentType::kStepped;
    case v1::SEGMENT_INVERSE_STEPPED:
      return SegmentType::kInverseStepped;
    default:
      return SegmentType::kLinear;
  }
}

CurvePoint PointFromProto(const v1::CurvePoint& p) { return {p.frame(), p.value()}; }

}  // namespace

std::vector<double> SampleInputCurve(const v1::CurveSet& set, int index) {
  const v1::Curve& proto = set.curves(index);
  Curve curve;
  curve.id = proto.id();
  curve.samples.assign(proto.samples().begin(), proto.samples().end());
  curve.start = PointFromProto(proto.start());
  for (const v1::CurveSegment& s : proto.segments()) {
    CurveSegment segment;
    segment.type = TypeFromProto(s.type());
    segment.handles[0] = PointFromProto(s.handle1());
    segment.handles[1] = PointFromProto(s.handle2());
    segment.end = PointFromProto(s.end());
    curve.segments.push_back(segment);
  }
  return SampleEveryFrame(curve, set.frame_count(), set.beziers_restricted());
}

}  // namespace koma::client::report

#include "convert/curves_convert.h"

namespace koma::convert {
namespace {

void PointToProto(const CurvePoint& p, v1::CurvePoint* out) {
  out->set_frame(p.frame);
  out->set_value(p.value);
}

v1::SegmentType SegmentTypeToProto(SegmentType type) {
  switch (type) {
    case SegmentType::kLinear:
      return v1::SEGMENT_LINEAR;
    case SegmentType::kBezier:
      return v1::SEGMENT_BEZIER;
    case SegmentType::kStepped:
      return v1::SEGMENT_STEPPED;
    case SegmentType::kInverseStepped:
      return v1::SEGMENT_INVERSE_STEPPED;
  }
  return v1::SEGMENT_TYPE_UNSPECIFIED;
}

void CurveToProto(const Curve& curve, v1::Curve* out) {
  out->set_id(curve.id);
  if (curve.dense()) {
    out->mutable_samples()->Add(curve.samples.begin(), curve.samples.end());
    return;
  }
  PointToProto(curve.start, out->mutable_start());
  for (const CurveSegment& segment : curve.segments) {
    v1::CurveSegment* s = out->add_segments();
    s->set_type(SegmentTypeToProto(segment.type));
    if (segment.type == SegmentType::kBezier) {
      PointToProto(segment.handles[0], s->mutable_handle1());
      PointToProto(segment.handles[1], s->mutable_handle2());
    }
    PointToProto(segment.end, s->mutable_end());
  }
}

}  // namespace

v1::CurveSet CurveSetToProto(const CurveSet& set) {
  v1::CurveSet out;
  out.set_fps(set.fps);
  out.set_frame_count(set.frame_count);
  out.set_beziers_restricted(set.beziers_restricted);
  for (const Curve& curve : set.curves) CurveToProto(curve, out.add_curves());
  return out;
}

std::vector<CurvePoint> StepsFromProto(const v1::Curve& stepped) {
  std::vector<CurvePoint> steps;
  steps.reserve(stepped.segments_size() + 1);
  steps.push_back({stepped.start().frame(), stepped.start().value()});
  for (const v1::CurveSegment& s : stepped.segments()) {
    steps.push_back({s.end().frame(), s.end().value()});
  }
  return steps;
}

DrawingTiming TimingFromProto(const v1::DrawingTiming& timing) {
  DrawingTiming out;
  out.frames_per_drawing = timing.frames_per_drawing();
  out.drawing_of_frame.assign(timing.drawing_of_frame().begin(), timing.drawing_of_frame().end());
  out.source_frame.assign(timing.source_frame().begin(), timing.source_frame().end());
  out.drawing_start.assign(timing.drawing_start().begin(), timing.drawing_start().end());
  return out;
}

const char* MouthShapeName(int shape) {
  switch (shape) {
    case v1::MOUTH_CLOSED:
      return "closed";
    case v1::MOUTH_MID:
      return "mid";
    case v1::MOUTH_OPEN:
      return "open";
    default:
      return "unspecified";
  }
}

}  // namespace koma::convert

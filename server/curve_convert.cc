#include "server/curve_convert.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"

namespace koma::server {
namespace {

CurvePoint PointFromProto(const v1::CurvePoint& p) { return {p.frame(), p.value()}; }

void PointToProto(const CurvePoint& p, v1::CurvePoint* out) {
  out->set_frame(p.frame);
  out->set_value(p.value);
}

// `path` makes the segment's field path; it is only called on an error (a string per segment
// would be made for every valid segment otherwise).
template <typename PathFn>
absl::StatusOr<SegmentType> SegmentTypeFromProto(int type, const PathFn& path) {
  switch (type) {
    case v1::SEGMENT_LINEAR:
      return SegmentType::kLinear;
    case v1::SEGMENT_BEZIER:
      return SegmentType::kBezier;
    case v1::SEGMENT_STEPPED:
      return SegmentType::kStepped;
    case v1::SEGMENT_INVERSE_STEPPED:
      return SegmentType::kInverseStepped;
    default:
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ".type: ", type,
          " is not a segment type (1 LINEAR, 2 BEZIER, 3 STEPPED, 4 INVERSE_STEPPED)"));
  }
}

// `path` makes the curve's field path ("curves.curves[2]"); like the segments' it is only
// called on an error (a path string per curve was a malloc per curve on every request).
template <typename PathFn>
absl::StatusOr<Curve> CurveFromProto(const v1::Curve& proto, const PathFn& path) {
  Curve curve;
  curve.id = proto.id();
  const bool keyframes = proto.has_start() || proto.segments_size() > 0;
  if (proto.samples_size() > 0) {
    if (keyframes) {
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ": both keyframes (start/segments) and samples are set; give one form"));
    }
    curve.samples.assign(proto.samples().begin(), proto.samples().end());
    return curve;
  }
  if (!proto.has_start()) {
    return absl::InvalidArgumentError(
        absl::StrCat(path(), ": empty curve (neither start nor samples is set)"));
  }
  curve.start = PointFromProto(proto.start());
  // Each segment is written where it stays: a local copied in by push_back was read back
  // with wide loads right after its narrow stores (the type), a store-forwarding stall per
  // segment that perf put at ~half of this conversion.
  curve.segments.resize(static_cast<size_t>(proto.segments_size()));
  for (int s = 0; s < proto.segments_size(); ++s) {
    const v1::CurveSegment& in = proto.segments(s);
    CurveSegment& segment = curve.segments[static_cast<size_t>(s)];
    KOMA_ASSIGN_OR_RETURN(segment.type, SegmentTypeFromProto(in.type(), [&] {
                            return absl::StrCat(path(), ".segments[", s, "]");
                          }));
    segment.handles[0] = PointFromProto(in.handle1());
    segment.handles[1] = PointFromProto(in.handle2());
    segment.end = PointFromProto(in.end());
  }
  return curve;
}

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

absl::Status Prefixed(const absl::Status& status, absl::string_view prefix) {
  if (status.ok()) return status;
  return absl::Status(status.code(), absl::StrCat(prefix, status.message()));
}

}  // namespace

absl::StatusOr<CurveSet> CurveSetFromProto(const v1::CurveSet& proto, absl::string_view path,
                                           const RequestLimits& limits) {
  KOMA_RETURN_IF_ERROR(CheckSize(proto, path, limits));
  CurveSet set;
  set.fps = proto.fps();
  set.frame_count = proto.frame_count();
  set.beziers_restricted = proto.beziers_restricted();
  set.curves.reserve(proto.curves_size());
  for (int i = 0; i < proto.curves_size(); ++i) {
    KOMA_ASSIGN_OR_RETURN(Curve curve, CurveFromProto(proto.curves(i), [&] {
                            return absl::StrCat(path, ".curves[", i, "]");
                          }));
    set.curves.push_back(std::move(curve));
  }
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateCurveSet(set), absl::StrCat(path, ".")));
  return set;
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

void SteppedKeyframesToProto(const std::vector<CurvePoint>& steps, v1::Curve* out) {
  if (steps.empty()) return;
  PointToProto(steps.front(), out->mutable_start());
  out->mutable_segments()->Reserve(static_cast<int>(steps.size()) - 1);
  for (size_t k = 1; k < steps.size(); ++k) {
    v1::CurveSegment* segment = out->add_segments();
    segment->set_type(v1::SEGMENT_STEPPED);
    PointToProto(steps[k], segment->mutable_end());
  }
}

}  // namespace koma::server

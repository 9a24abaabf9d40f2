#include "convert/curves_convert.h"

#include "absl/strings/str_cat.h"
#include "convert/field_error.h"
#include "core/status_macros.h"

namespace koma::convert {
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
absl::StatusOr<Curve> CurveFromProtoAt(const v1::Curve& proto, const PathFn& path) {
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
    segment.inserted = in.inserted();
  }
  return curve;
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
    if (segment.inserted) s->set_inserted(true);
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

absl::StatusOr<CurveSet> CurveSetFromProto(const v1::CurveSet& proto, absl::string_view path) {
  CurveSet set;
  set.fps = proto.fps();
  set.frame_count = proto.frame_count();
  set.beziers_restricted = proto.beziers_restricted();
  set.curves.reserve(proto.curves_size());
  for (int i = 0; i < proto.curves_size(); ++i) {
    KOMA_ASSIGN_OR_RETURN(Curve curve, CurveFromProtoAt(proto.curves(i), [&] {
                            return absl::StrCat(path, ".curves[", i, "]");
                          }));
    set.curves.push_back(std::move(curve));
  }
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateCurveSet(set), absl::StrCat(path, ".")));
  return set;
}

absl::StatusOr<Curve> CurveFromProto(const v1::Curve& proto, absl::string_view path) {
  return CurveFromProtoAt(proto, [path] { return std::string(path); });
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

std::vector<CurvePoint> StepsFromProto(const v1::Curve& stepped) {
  std::vector<CurvePoint> steps;
  steps.reserve(stepped.segments_size() + 1);
  steps.push_back(PointFromProto(stepped.start()));
  for (const v1::CurveSegment& s : stepped.segments()) steps.push_back(PointFromProto(s.end()));
  return steps;
}

CurveReplacement ReplacementFromProto(const v1::RetimedCurve& curve) {
  return {std::vector<double>(curve.values().begin(), curve.values().end()),
          StepsFromProto(curve.stepped())};
}

CurveReplacement ReplacementFromProto(const v1::ConvertedCurve& curve) {
  return {std::vector<double>(curve.values().begin(), curve.values().end()),
          StepsFromProto(curve.stepped())};
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

std::vector<std::vector<std::string>> KeysByDrawing(const v1::RetimeCurvesResponse& response,
                                                    int timing) {
  if (timing < 0 || timing >= response.timings_size()) return {};
  std::vector<std::vector<std::string>> ids(
      static_cast<size_t>(response.timings(timing).drawing_start_size()));
  for (const v1::RetimedCurve& curve : response.curves()) {
    if (curve.timing() != timing) continue;
    for (const v1::KeyDrawing& key : curve.keys()) {
      if (!key.drawn() || key.drawing() < 0 || static_cast<size_t>(key.drawing()) >= ids.size()) {
        continue;
      }
      std::vector<std::string>& names = ids[static_cast<size_t>(key.drawing())];
      if (names.empty() || names.back() != curve.id()) names.push_back(curve.id());
    }
  }
  return ids;
}

v1::KeyRole KeyRoleToProto(KeyRole role) {
  switch (role) {
    case KeyRole::kFirst:
      return v1::KEY_ROLE_FIRST;
    case KeyRole::kLast:
      return v1::KEY_ROLE_LAST;
    case KeyRole::kExtreme:
      break;
  }
  return v1::KEY_ROLE_EXTREME;
}

void KeyDrawingToProto(const KeyDrawing& key, v1::KeyDrawing* out) {
  out->set_frame(key.frame);
  out->set_value(key.value);
  out->set_role(KeyRoleToProto(key.role));
  out->set_drawing(key.drawing);
  out->set_drawn(key.drawn);
  out->set_displaced(key.displaced);
}

v1::CurveTimingGroupMode TimingGroupModeToProto(TimingGroupMode mode) {
  switch (mode) {
    case TimingGroupMode::kKeep:
      return v1::GROUP_KEEP;
    case TimingGroupMode::kLipBlink:
      return v1::GROUP_LIP_BLINK;
    case TimingGroupMode::kStep:
      break;
  }
  return v1::GROUP_STEP;
}

std::map<std::string, v1::CurveTimingGroupMode> TimingGroupModes(
    const v1::RetimeCurvesRequest& request) {
  std::map<std::string, v1::CurveTimingGroupMode> modes;
  for (const v1::CurveTimingGroup& g : request.timing_groups()) {
    modes.emplace(g.name(), g.mode() == v1::CURVE_TIMING_GROUP_MODE_UNSPECIFIED ? v1::GROUP_STEP
                                                                                 : g.mode());
  }
  if (request.timing_groups_size() == 0 &&
      (!request.has_default_timing_groups() || request.default_timing_groups())) {
    for (const CurveTimingGroup& g : DefaultLive2dTimingGroups()) {
      modes.emplace(g.name, TimingGroupModeToProto(g.mode));
    }
  }
  return modes;
}

const char* TimingGroupModeName(v1::CurveTimingGroupMode mode) {
  switch (mode) {
    case v1::GROUP_KEEP:
      return "keep";
    case v1::GROUP_LIP_BLINK:
      return "lipblink";
    default:
      return "step";
  }
}

}  // namespace koma::convert

// Animation curves (2D skeletal / Live2D parameters): types, validation, evaluation at
// fractional frames with motion3.json's rules. Used by RetimeCurves and LipBlink.
//
// Time is in frames of the curve set's frame rate (fps), fractional where a keyframe sits
// between frames; seconds exist only in files (motion3.json), converted at the edge.
#ifndef KOMA_CORE_CURVES_H_
#define KOMA_CORE_CURVES_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"

namespace koma {

// motion3.json's four segment types, with their numeric identifiers there.
enum class SegmentType : uint8_t {
  kLinear = 0,          // straight line from the previous point to `end`
  kBezier = 1,          // cubic Bezier: previous point, handles[0], handles[1], end
  kStepped = 2,         // the previous point's value until `end.frame`, where it jumps
  kInverseStepped = 3,  // `end.value` right after the previous point
};

struct CurvePoint {
  double frame = 0.0;  // time in frames (fractional allowed)
  double value = 0.0;  // the parameter's value (unit of the parameter)
};

struct CurveSegment {
  SegmentType type = SegmentType::kLinear;
  CurvePoint handles[2];  // Bezier control points P1, P2; unused otherwise
  CurvePoint end;         // the segment's last point
  // True when a reader inserted `end` to approximate a curve between two keys (a Spine Bezier
  // with a handle outside its span, played as the runtimes' straight pieces): it is evaluated
  // like any point, but it is not a keyframe (no key pose, no key to draw).
  bool inserted = false;
};

struct Curve {
  std::string id;  // e.g. "ParamAngleX"; unique within a CurveSet
  // Keyframe form: `start` then `segments` (each starts where the previous ended).
  CurvePoint start;
  std::vector<CurveSegment> segments;
  // Dense form: one sample per frame 0 .. frame_count - 1, linear between samples. When
  // non-empty, `start` and `segments` are unused.
  std::vector<double> samples;

  bool dense() const { return !samples.empty(); }
};

struct CurveSet {
  double fps = 30.0;      // frames per second, > 0
  int frame_count = 0;    // frames 0 .. frame_count - 1; >= 2
  // motion3.json Meta.AreBeziersRestricted: true = a Bezier's parameter is linear in time
  // (handle times ignored); false = solve x(u) = time for u on the handles' times.
  bool beziers_restricted = false;
  std::vector<Curve> curves;
};

// Rules, each INVALID_ARGUMENT naming the path ("curves[2].segments[4].end.frame") and the
// value:
//  1. fps finite and > 0; frame_count >= 2; at least one curve;
//  2. ids non-empty and unique;
//  3. every number finite;
//  4. keyframe form: segment end frames strictly increase, starting after `start.frame`;
//  5. Bezier handles lie within their segment's time span, and in restricted mode are in
//     order (P0.t <= P1.t <= P2.t <= P3.t);
//  6. dense form: exactly frame_count samples.
absl::Status ValidateCurveSet(const CurveSet& set);

// The curve's value at time `frame` (motion3.json's rules: before the first point the first
// segment is clamped to its start; at or after the last point, the last point's value; a
// point's time belongs to the segment that starts there). Requires a valid curve.
// Deterministic: only +, -, *, / and comparisons (a Bezier in unrestricted mode is solved by
// bisection, not Cardano's formula, whose cbrt/acos differ between libm versions).
double EvaluateCurve(const Curve& curve, double frame, bool beziers_restricted);

// Per-frame values (frame f = values[f]) as stepped keyframes: a point at frame 0, one at
// every frame whose value differs from the previous frame's, and one at the last frame, so
// the curve spans the whole clip (at least 2 points when there are at least 2 frames).
// Evaluated with stepped segments, they give back values[f] at every frame f.
std::vector<CurvePoint> SteppedFromValues(const std::vector<double>& values);

// The curve's value at every frame 0 .. frame_count - 1 (dense samples as they are).
std::vector<double> SampleEveryFrame(const Curve& curve, int frame_count,
                                     bool beziers_restricted);

}  // namespace koma

#endif  // KOMA_CORE_CURVES_H_

#include "core/curves.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "core/curve_cursor.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"

namespace koma {
namespace {

// Bisection halves [0, 1] at most this often: 2^-64 is far below a double's resolution of the
// parameter near 1, so the loop normally ends earlier, when the interval stops shrinking.
constexpr int kBisectionSteps = 64;

// The checks below take the field's path as a callable that builds it: the path string is
// only made when a check fails, because a valid request has millions of values and making
// one string per value cost more than the whole retiming (profiled: ~40 % of a LipBlink call).
template <typename PathFn>
absl::Status CheckFinite(double value, const PathFn& path) {
  if (std::isfinite(value)) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(path(), ": ", value, " is not finite"));
}

template <typename PathFn>
absl::Status CheckPoint(const CurvePoint& point, const PathFn& path) {
  KOMA_RETURN_IF_ERROR(CheckFinite(point.frame, [&] { return absl::StrCat(path(), ".frame"); }));
  return CheckFinite(point.value, [&] { return absl::StrCat(path(), ".value"); });
}

// Rule 5 for the Bezier segment `segment` that starts at `from`; `path` makes the segment's.
template <typename PathFn>
absl::Status CheckBezierHandles(const CurvePoint& from, const CurveSegment& segment,
                                const PathFn& path, bool beziers_restricted) {
  for (int k = 0; k < 2; ++k) {
    const auto handle = [&] { return absl::StrCat(path(), ".handles[", k, "]"); };
    KOMA_RETURN_IF_ERROR(CheckPoint(segment.handles[k], handle));
    const double frame = segment.handles[k].frame;
    if (frame < from.frame || frame > segment.end.frame) {
      return absl::InvalidArgumentError(absl::StrCat(handle(), ".frame: ", frame,
                                                     " is outside the segment's time span [",
                                                     from.frame, ", ", segment.end.frame, "]"));
    }
  }
  if (beziers_restricted && segment.handles[1].frame < segment.handles[0].frame) {
    return absl::InvalidArgumentError(absl::StrCat(
        path(), ".handles[1].frame: ", segment.handles[1].frame, " is before handles[0].frame ",
        segment.handles[0].frame, " (restricted Beziers need P0 <= P1 <= P2 <= P3 in time)"));
  }
  return absl::OkStatus();
}

template <typename PathFn>
absl::Status CheckSegment(const CurvePoint& from, const CurveSegment& segment, const PathFn& path,
                          bool beziers_restricted) {
  const int type = static_cast<int>(segment.type);
  if (type > static_cast<int>(SegmentType::kInverseStepped)) {
    return absl::InvalidArgumentError(absl::StrCat(path(), ".type: ", type,
                                                   " is not a segment type (0 linear, 1 bezier, "
                                                   "2 stepped, 3 inverse stepped)"));
  }
  KOMA_RETURN_IF_ERROR(CheckPoint(segment.end, [&] { return absl::StrCat(path(), ".end"); }));
  if (!(segment.end.frame > from.frame)) {
    return absl::InvalidArgumentError(
        absl::StrCat(path(), ".end.frame: ", segment.end.frame,
                     " must be greater than the previous point's frame ", from.frame));
  }
  if (segment.type != SegmentType::kBezier) return absl::OkStatus();
  return CheckBezierHandles(from, segment, path, beziers_restricted);
}

template <typename PathFn>
absl::Status CheckCurve(const Curve& curve, const PathFn& path, int frame_count,
                        bool beziers_restricted) {
  if (curve.dense()) {
    if (curve.samples.size() != static_cast<size_t>(frame_count)) {
      return absl::InvalidArgumentError(absl::StrCat(path(), ".samples: expected ", frame_count,
                                                     " values (frame_count), got ",
                                                     curve.samples.size()));
    }
    if (AllFinite(curve.samples)) return absl::OkStatus();  // one vectorised pass
    for (size_t k = 0; k < curve.samples.size(); ++k) {
      KOMA_RETURN_IF_ERROR(
          CheckFinite(curve.samples[k], [&] { return absl::StrCat(path(), ".samples[", k, "]"); }));
    }
    return absl::OkStatus();
  }
  KOMA_RETURN_IF_ERROR(CheckPoint(curve.start, [&] { return absl::StrCat(path(), ".start"); }));
  const CurvePoint* from = &curve.start;
  for (size_t s = 0; s < curve.segments.size(); ++s) {
    KOMA_RETURN_IF_ERROR(CheckSegment(
        *from, curve.segments[s], [&] { return absl::StrCat(path(), ".segments[", s, "]"); },
        beziers_restricted));
    from = &curve.segments[s].end;
  }
  return absl::OkStatus();
}

// a + (b - a) * u: exact at u = 0 and when a == b (a flat stretch stays flat to the bit).
double Lerp(double a, double b, double u) { return a + (b - a) * u; }

// The cubic Bezier (Bernstein form) with control values p0..p3 at parameter u, by de
// Casteljau's construction.
double Cubic(double p0, double p1, double p2, double p3, double u) {
  const double a = Lerp(p0, p1, u);
  const double b = Lerp(p1, p2, u);
  const double c = Lerp(p2, p3, u);
  return Lerp(Lerp(a, b, u), Lerp(b, c, u), u);
}

// The parameter u in [0, 1] where the cubic on times t0..t3 reaches `frame`. Rule 5 keeps the
// handles inside [t0, t3], which makes that cubic non-decreasing, so bisection finds the
// crossing; it uses only +, -, * and comparisons, so every machine gets the same bits.
double SolveBezierParameter(double t0, double t1, double t2, double t3, double frame) {
  if (frame <= t0) return 0.0;
  if (frame >= t3) return 1.0;
  // x(u) - t0 = ((a u + b) u + c) u in power form: half the dependent operations of de
  // Casteljau's, which matters over ~55 bisection steps.
  const double c = 3.0 * (t1 - t0);
  const double b = 3.0 * ((t2 - t1) - (t1 - t0));
  const double a = (t3 - t0) - 3.0 * (t2 - t1);
  const double target = frame - t0;
  double lo = 0.0;
  double hi = 1.0;
  for (int step = 0; step < kBisectionSteps; ++step) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;  // lo and hi are adjacent doubles
    if (((a * mid + b) * mid + c) * mid < target) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

// Linear between the samples at integer frames, held at both ends.
double EvaluateDense(const std::vector<double>& samples, double frame) {
  if (!(frame > 0.0)) return samples.front();  // also a NaN frame, rather than a bad index
  const double last = static_cast<double>(samples.size() - 1);
  if (frame >= last) return samples.back();
  const size_t i = static_cast<size_t>(frame);  // floor: frame is in (0, last)
  return Lerp(samples[i], samples[i + 1], frame - static_cast<double>(i));
}

// The first segment whose end is after `frame` (segments.size() when there is none).
size_t FindSegment(const Curve& curve, double frame) {
  const auto it = std::partition_point(
      curve.segments.begin(), curve.segments.end(),
      [frame](const CurveSegment& segment) { return segment.end.frame <= frame; });
  return static_cast<size_t>(it - curve.segments.begin());
}

// A keyframe curve at `frame`, which falls in segment `index` (FindSegment's answer).
// Before the first point every type gives the first point's value: the parameter clamped to
// 0 for linear, Bezier and stepped segments, and for an inverse-stepped first segment a
// deliberate choice (Cubism's runtime returns its end value there) so that a curve never
// shows a value before its first key.
double EvaluateKeyframesAt(const Curve& curve, size_t index, double frame,
                           bool beziers_restricted) {
  if (curve.segments.empty() || frame < curve.start.frame) return curve.start.value;
  if (index >= curve.segments.size()) return curve.segments.back().end.value;
  const CurvePoint& from = index == 0 ? curve.start : curve.segments[index - 1].end;
  return EvaluateSegment(from, curve.segments[index], frame, beziers_restricted);
}

}  // namespace

absl::Status ValidateCurveSet(const CurveSet& set) {
  if (!std::isfinite(set.fps) || !(set.fps > 0.0)) {
    return absl::InvalidArgumentError(absl::StrCat("fps: ", set.fps, " must be finite and > 0"));
  }
  if (set.frame_count < 2) {
    return absl::InvalidArgumentError(
        absl::StrCat("frame_count: ", set.frame_count, " must be >= 2 (a first and a last frame)"));
  }
  if (set.curves.empty()) return absl::InvalidArgumentError("curves: no curves");
  // Views of the ids (the set outlives the table), one allocation: a std::map copied every id
  // into a node of its own (two mallocs per curve on every request). The path is formatted
  // only for an error, like the values' paths.
  absl::flat_hash_map<absl::string_view, size_t> first_with_id;
  first_with_id.reserve(set.curves.size());
  for (size_t c = 0; c < set.curves.size(); ++c) {
    const auto path = [c] { return absl::StrCat("curves[", c, "]"); };
    const Curve& curve = set.curves[c];
    if (curve.id.empty()) return absl::InvalidArgumentError(absl::StrCat(path(), ".id: is empty"));
    const auto [it, inserted] = first_with_id.emplace(curve.id, c);
    if (!inserted) {
      return absl::InvalidArgumentError(absl::StrCat(
          path(), ".id: \"", curve.id, "\" is already the id of curves[", it->second, "]"));
    }
    KOMA_RETURN_IF_ERROR(CheckCurve(curve, path, set.frame_count, set.beziers_restricted));
  }
  return absl::OkStatus();
}

double EvaluateSegment(const CurvePoint& from, const CurveSegment& segment, double frame,
                       bool beziers_restricted) {
  const CurvePoint& to = segment.end;
  switch (segment.type) {
    case SegmentType::kStepped:
      return from.value;
    case SegmentType::kInverseStepped:
      return to.value;
    case SegmentType::kBezier:
      if (!beziers_restricted) {
        const double u = SolveBezierParameter(from.frame, segment.handles[0].frame,
                                              segment.handles[1].frame, to.frame, frame);
        return Cubic(from.value, segment.handles[0].value, segment.handles[1].value, to.value, u);
      }
      break;
    case SegmentType::kLinear:
      break;
  }
  // Linear, and restricted Bezier: the parameter is linear in time.
  const double u = std::clamp((frame - from.frame) / (to.frame - from.frame), 0.0, 1.0);
  if (segment.type == SegmentType::kLinear) return Lerp(from.value, to.value, u);
  return Cubic(from.value, segment.handles[0].value, segment.handles[1].value, to.value, u);
}

double EvaluateCurve(const Curve& curve, double frame, bool beziers_restricted) {
  if (curve.dense()) return EvaluateDense(curve.samples, frame);
  return EvaluateKeyframesAt(curve, FindSegment(curve, frame), frame, beziers_restricted);
}

double CurveCursor::Evaluate(double frame) {
  if (curve_.dense()) return EvaluateDense(curve_.samples, frame);
  const std::vector<CurveSegment>& segments = curve_.segments;
  if (segment_ > 0 && !(segments[segment_ - 1].end.frame <= frame)) {
    segment_ = FindSegment(curve_, frame);  // went back before the remembered segment
  }
  while (segment_ < segments.size() && segments[segment_].end.frame <= frame) ++segment_;
  return EvaluateKeyframesAt(curve_, segment_, frame, beziers_restricted_);
}

std::vector<CurvePoint> SteppedFromValues(const std::vector<double>& values) {
  std::vector<CurvePoint> steps;
  for (size_t f = 0; f < values.size(); ++f) {
    const bool last = f + 1 == values.size();
    if (f == 0 || values[f] != values[f - 1] || (last && f > 0)) {
      steps.push_back({static_cast<double>(f), values[f]});
    }
  }
  return steps;
}

double CurveCursor::EvaluateSharing(double frame, double& parameter, bool known) {
  if (curve_.dense()) return Evaluate(frame);
  const std::vector<CurveSegment>& segments = curve_.segments;
  if (segment_ > 0 && !(segments[segment_ - 1].end.frame <= frame)) {
    segment_ = FindSegment(curve_, frame);  // went back before the remembered segment
  }
  while (segment_ < segments.size() && segments[segment_].end.frame <= frame) ++segment_;
  // EvaluateKeyframesAt, with the Bezier parameter shared.
  if (beziers_restricted_ || segments.empty() || frame < curve_.start.frame ||
      segment_ >= segments.size() || segments[segment_].type != SegmentType::kBezier) {
    if (!known) parameter = std::numeric_limits<double>::quiet_NaN();
    return EvaluateKeyframesAt(curve_, segment_, frame, beziers_restricted_);
  }
  const CurvePoint& from = segment_ == 0 ? curve_.start : segments[segment_ - 1].end;
  const CurveSegment& segment = segments[segment_];
  if (!known) {
    parameter = SolveBezierParameter(from.frame, segment.handles[0].frame,
                                     segment.handles[1].frame, segment.end.frame, frame);
  }
  return Cubic(from.value, segment.handles[0].value, segment.handles[1].value, segment.end.value,
               parameter);
}

bool SameCurveTimes(const Curve& a, const Curve& b) {
  if (a.dense() || b.dense() || a.start.frame != b.start.frame ||
      a.segments.size() != b.segments.size()) {
    return false;
  }
  for (size_t s = 0; s < a.segments.size(); ++s) {
    const CurveSegment& x = a.segments[s];
    const CurveSegment& y = b.segments[s];
    if (x.type != y.type || x.end.frame != y.end.frame) return false;
    if (x.type == SegmentType::kBezier && (x.handles[0].frame != y.handles[0].frame ||
                                           x.handles[1].frame != y.handles[1].frame)) {
      return false;
    }
  }
  return true;
}

std::vector<double> SampleEveryFrame(const Curve& curve, int frame_count, bool beziers_restricted) {
  if (curve.dense()) return curve.samples;
  std::vector<double> values(frame_count);
  CurveCursor cursor(curve, beziers_restricted);  // times only increase: O(frames + segments)
  for (int f = 0; f < frame_count; ++f) values[f] = cursor.Evaluate(f);
  return values;
}

}  // namespace koma

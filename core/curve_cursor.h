// Internal to core/: evaluating one curve at many non-decreasing times in O(times + segments)
// (EvaluateCurve alone binary-searches the segment, O(log segments) per call). RetimeCurves
// samples every curve at its drawings' source times, which never go backwards.
#ifndef KOMA_CORE_CURVE_CURSOR_H_
#define KOMA_CORE_CURVE_CURSOR_H_

#include <cstddef>

#include "core/curves.h"

namespace koma {

// The value of `segment`, which starts at point `from`, at time `frame` (in frames), for
// from.frame <= frame < segment.end.frame; an earlier time clamps the parameter to 0, a later
// one to 1. Bezier handles are used as motion3.json's AreBeziersRestricted says.
double EvaluateSegment(const CurvePoint& from, const CurveSegment& segment, double frame,
                       bool beziers_restricted);

// Same answers as EvaluateCurve, bit for bit. Remembers the segment of the last call: a time
// at or after it walks forward, an earlier one falls back to EvaluateCurve's binary search.
// Holds a reference: `curve` must outlive the cursor.
class CurveCursor {
 public:
  CurveCursor(const Curve& curve, bool beziers_restricted)
      : curve_(curve), beziers_restricted_(beziers_restricted) {}

  double Evaluate(double frame);

  // Evaluate(frame) for a curve whose times equal those of a curve already evaluated at the
  // same frames (SameCurveTimes): an unrestricted Bezier's parameter at `frame` depends only
  // on the segment's times, so `parameter` carries it from one curve to the next. `known`:
  // `parameter` holds it (the solve is skipped); else it receives it (NaN when `frame` does
  // not fall in an unrestricted Bezier segment). Same answers as Evaluate, bit for bit.
  double EvaluateSharing(double frame, double& parameter, bool known);

 private:
  const Curve& curve_;
  bool beziers_restricted_;
  size_t segment_ = 0;  // index of the segment the last time fell in (or segments.size())
};

// True when `a` and `b` are keyframe curves with the same times: start frame, segment count,
// and per segment its type, end frame and (for a Bezier) handle frames, all equal. Such curves
// share every Bezier parameter at every time (CurveCursor::EvaluateSharing).
bool SameCurveTimes(const Curve& a, const Curve& b);

}  // namespace koma

#endif  // KOMA_CORE_CURVE_CURSOR_H_

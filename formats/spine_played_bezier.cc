// SpinePlayedBezier: the runtimes' samples of a Bezier, then the pieces a time can reach.
#include "formats/spine_played_bezier.h"

#include <algorithm>
#include <cmath>

namespace koma::formats {
namespace {

// The Bezier's point at parameter u in [0, 1], Bernstein form (+, -, * only: deterministic).
CurvePoint BezierPoint(const CurvePoint c[4], double u) {
  const double w = 1.0 - u;
  const double b0 = w * w * w, b1 = 3.0 * w * w * u, b2 = 3.0 * w * u * u, b3 = u * u * u;
  return {b0 * c[0].frame + b1 * c[1].frame + b2 * c[2].frame + b3 * c[3].frame,
          b0 * c[0].value + b1 * c[1].value + b2 * c[2].value + b3 * c[3].value};
}

}  // namespace

std::vector<CurvePoint> SpinePlayedBezier(const CurvePoint controls[4]) {
  // The runtimes' points: the keys and the samples between them.
  CurvePoint samples[kSpineBezierPieces + 1];
  samples[0] = controls[0];
  for (int k = 1; k < kSpineBezierPieces; ++k) {
    samples[k] = BezierPoint(controls, static_cast<double>(k) / kSpineBezierPieces);
  }
  samples[kSpineBezierPieces] = controls[3];
  const double end = controls[3].frame;

  std::vector<CurvePoint> points;
  // A point strictly after the previous one and before the next key; a ramp point that would
  // not be (its piece narrower than the ramp) is left out.
  const auto add = [&points, &controls, end](double frame, double value) {
    const double previous = points.empty() ? controls[0].frame : points.back().frame;
    if (frame > previous && frame < end) points.push_back(CurvePoint{frame, value});
  };
  // A time t is played on the first piece whose end is at or after t. So piece k plays only
  // the times past every sample before it: (reached, its end], where `reached` is the latest
  // time of samples 0 .. k-1 (k's start may lie before `reached` when the time ran back).
  double reached = controls[0].frame;
  for (int k = 1; k <= kSpineBezierPieces; ++k) {
    const CurvePoint& a = samples[k - 1];
    const CurvePoint& b = samples[k];
    if (!(b.frame > reached)) continue;  // ends at or before a time already played: never shown
    // a.frame <= reached < b.frame, so the piece's line is defined.
    const auto line = [&a, &b](double t) {
      return a.value + (t - a.frame) * (b.value - a.value) / (b.frame - a.frame);
    };
    if (a.frame < reached) {  // the value jumps onto this piece's line just after `reached`
      const double t = std::min(reached + kSpineJumpFrames, std::min(b.frame, end));
      add(t, line(t));
    }
    if (b.frame < end) {
      add(b.frame, b.value);
      reached = b.frame;
      continue;
    }
    // This piece reaches the next key's time. Before the last piece (whose end is the key) the
    // runtime shows the piece's line until the key's time, then the key's value: a jump.
    if (k < kSpineBezierPieces) add(end - kSpineJumpFrames, line(end - kSpineJumpFrames));
    break;
  }
  points.push_back(controls[3]);
  for (const CurvePoint& p : samples) {
    if (!std::isfinite(p.frame) || !std::isfinite(p.value)) return {};
  }
  for (const CurvePoint& p : points) {
    if (!std::isfinite(p.value)) return {};
  }
  return points;
}

}  // namespace koma::formats

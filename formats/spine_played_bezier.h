// A Spine Bezier whose handles leave its segment's time span, as Spine's runtimes play it.
//
// The Spine editor lets a Bezier's handle go before the key or past the next one in time
// (Esoteric Software's own example skeletons have such curves), and every runtime plays them.
// The runtimes do not solve the Bezier for a time: when a skeleton loads they sample it at
// kSpineBezierPieces - 1 evenly spaced parameters (u = 0.1, 0.2, ..., 0.9) between the two
// keys and, for a time t, take the first sampled point at or after t and interpolate linearly
// from the sampled point before it. With a handle outside the span the Bezier's time runs
// backwards somewhere, so some pieces are never reached and the played value jumps where the
// sampled time turns back forward past where it had already been. (Observed behaviour of
// the runtimes, docs/formats.md; written from that description, not from runtime code.)
// Inside its span a Bezier is not converted: core solves it exactly (docs/semantics.md).
#ifndef KOMA_FORMATS_SPINE_PLAYED_BEZIER_H_
#define KOMA_FORMATS_SPINE_PLAYED_BEZIER_H_

#include <vector>

#include "core/curves.h"

namespace koma::formats {

// Straight pieces per Bezier in the runtimes: points at u = k / 10, k = 0 .. 10.
inline constexpr int kSpineBezierPieces = 10;

// Width (frames) of the straight ramp that stands for a jump of the played value: core's
// curves take no two points at one time.
inline constexpr double kSpineJumpFrames = 1e-3;

// The Bezier from key controls[0] through handles controls[1] and controls[2] to key
// controls[3] (frames and values; controls[0].frame < controls[3].frame), as the runtimes play
// it: points to join by straight lines after controls[0], in strictly increasing frames, the
// last exactly controls[3]. What is approximated, all within kSpineJumpFrames of a jump or in
// the last bits of a double:
//  - a jump of the played value is a ramp kSpineJumpFrames wide: just after the frame where
//    the sampled time comes back past where it had been, or just before controls[3] when the
//    samples pass the next key before reaching it (the runtimes show the next key from its
//    time on, so the value jumps there);
//  - at controls[0]'s own frame the key's value (a runtime whose first samples go back before
//    the key shows the value of the first piece that reaches past it);
//  - the samples are computed in double from the Bernstein form (the runtimes use single
//    precision forward differences).
// Empty when the handles are too far out for doubles (a sample or value is not finite).
std::vector<CurvePoint> SpinePlayedBezier(const CurvePoint controls[4]);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_SPINE_PLAYED_BEZIER_H_

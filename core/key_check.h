// The key check (`koma curves --check-keys`, docs/semantics.md, "Every key is drawn"): how
// well a retimed motion keeps the keys the animator set, measured from the input curves and the
// stepped curves koma wrote, independently of how koma chose them.
//
// For every moving curve (its keys' values are not all equal; the keys are its keyframes, or a
// dense curve's samples):
//  - each key that is a local extreme of the keys' values (a turn, or the edge of a
//    run of equal values) is *missed* when no drawing within `window` frames of it (on the
//    frames the timing is counted in: the grid's, or the source's) shows its value to within
//    `tolerance` of the curve's range (the range of its keyframe values);
//  - its ends are *missed* when the first drawing does not show the first keyframe's value, or
//    the last drawing the last keyframe's, to within the same tolerance;
//  - its drawings a second: the changes of its stepped value over the timing frames, plus one,
//    per second of clip ((frames - 1) / rate).
#ifndef KOMA_CORE_KEY_CHECK_H_
#define KOMA_CORE_KEY_CHECK_H_

#include <string>
#include <vector>

#include "core/curves.h"

namespace koma {

struct KeyCheckOptions {
  // The rate the timing is counted at, frames per second (the film grid's, 24 by default);
  // <= 0 counts in the set's own frames.
  double timing_fps = 24.0;
  int window = 3;            // frames either side of a key in which its value may be drawn
  double tolerance = 0.005;  // fraction of the curve's range a drawn value may differ by
};

struct CurveKeyCheck {
  std::string id;
  int extremes = 0;         // keyed extremes checked
  int extremes_missed = 0;  // of those, not drawn within the window and tolerance
  double worst_miss = 0.0;  // the largest miss, as a fraction of the range (0: none)
  double worst_miss_frame = 0.0;  // the time of that key, source frames
  bool first_missed = false;
  bool last_missed = false;
  int drawings = 0;  // visible drawings (value changes + 1) on the timing frames
};

struct KeyCheck {
  std::vector<CurveKeyCheck> curves;  // the moving curves checked, in the set's order
  int extremes = 0;
  int extremes_missed = 0;
  int ends_missed = 0;  // first and last keys missed, counted separately
  double seconds = 0.0;  // the clip's length on the timing frames
  // Drawings a second over the moving curves: median, p95 and maximum.
  double drawings_per_second_median = 0.0;
  double drawings_per_second_p95 = 0.0;
  double drawings_per_second_max = 0.0;
};

// `stepped[c]`: curve c of `input` as retimed, stepped keyframes (a point per drawing, its value
// held until the next point's time: RetimedCurve::steps, or the stepped curve of the response);
// null or empty for a curve not to check (kept as it came, or drawn by LipBlink). A dense
// curve's keys are its samples. Requires a valid `input`.
KeyCheck CheckKeys(const CurveSet& input, const std::vector<const std::vector<CurvePoint>*>& stepped,
                   const KeyCheckOptions& options = {});

}  // namespace koma

#endif  // KOMA_CORE_KEY_CHECK_H_

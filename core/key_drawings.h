// Every key is drawn (docs/semantics.md, "Every key is drawn"): which of a curve's own
// keyframes its drawings carry, and the source time each drawing shows of that curve.
//
// koma-uchi decides when drawings change (the merged key poses and holds, the same for every
// curve of a timing); this decides what each drawing shows of one curve. A drawing shows the
// curve at its spacing time tau, except that the curve's first and last keyframes and each
// keyframe that is a local extreme of its values are drawn exactly, in the drawing whose hold
// contains the key, and the drawings around them never step back in the curve's time.
#ifndef KOMA_CORE_KEY_DRAWINGS_H_
#define KOMA_CORE_KEY_DRAWINGS_H_

#include <vector>

#include "core/curves.h"

namespace koma {

// Why a keyframe must be drawn.
enum class KeyRole : unsigned char {
  kFirst,    // the curve's first keyframe
  kLast,     // its last keyframe (a loop's end meets its start)
  kExtreme,  // a local extreme of the keyframe values: a peak, a turn, the start or end of a hold
};

// One keyframe the rule draws.
struct KeyDrawing {
  double frame = 0.0;  // the key's time, in (fractional) source frames
  // Its input value, which the drawing shows exactly: the curve's value at the key's time (the
  // key's own value, or the next key's where an inverse-stepped segment starts at the key).
  double value = 0.0;
  KeyRole role = KeyRole::kExtreme;
  double swing = 0.0;  // largest change of value to a neighbouring keyframe (units of the curve)
  // The drawing that shows the key: the one whose hold contains it, or (displaced) the one
  // before or after it.
  int drawing = 0;
  // True when the key is shown by the drawing before or after the one whose hold contains it:
  // another key of the curve won that drawing, and no key fell in this one.
  bool displaced = false;
  // False when the key is not drawn: another key of the curve won the drawing whose hold
  // contains it, and the drawing on its side is taken too ("shared").
  bool drawn = true;
};

// The keys of a curve that must be drawn, in time order. A keyframe curve's keys are its start
// and every segment end not `inserted`; a dense curve's (a CSV's per-frame values) its samples.
// Drawn: the first and the last key, and every key whose value is a local extreme of the keys'
// values: the value turns there (rises then falls, or falls then rises) or a run of equal
// values starts or ends there (a hold the animator keyed); a key inside a flat run or on a
// monotone stretch is not. `drawing` is left 0. Empty for a curve whose keys all have one value
// (a Bezier's handles aside, nothing moves: every drawing shows that value).
std::vector<KeyDrawing> KeysToDraw(const Curve& curve);

// The source time each drawing shows of one curve, and its keys placed on the drawings.
struct CurveDrawingTimes {
  // Per drawing: the time (source frames) at which the curve is shown.
  std::vector<double> time;
  // Per drawing: index into `keys` of the key it carries, or -1.
  std::vector<int> key;
  // Per drawing: index into `keys` of the key whose time (and value) it shows: the key it
  // carries, or the carried key its tau was clamped to; -1 when it shows its own tau.
  std::vector<int> at_key;
  std::vector<KeyDrawing> keys;
};

// Places `keys` (KeysToDraw, each with its `drawing` set, non-decreasing in time) on the
// drawings whose spacing times are `tau` (non-decreasing, one per drawing):
//  - each drawing that contains keys carries one of them: the last key, else the first key,
//    else the extreme with the largest swing (the earliest of equal swings);
//  - a key that lost is carried by the drawing before (if it is earlier than the winner) or
//    after (if later) when no key falls in that drawing, the best of several by the same order
//    (displaced); the others are marked not drawn;
//  - a drawing that carries a key shows the key's time; every other drawing shows its tau
//    clamped between the times of the nearest carried keys before and after it, so the times
//    shown never go backwards (no drawing shows an earlier time of the curve than the one
//    before it). A tau at or beyond a carried key's time shows that key (at_key).
CurveDrawingTimes PlaceKeysOnDrawings(std::vector<KeyDrawing> keys, const std::vector<double>& tau);

}  // namespace koma

#endif  // KOMA_CORE_KEY_DRAWINGS_H_

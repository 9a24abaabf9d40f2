// LipBlink on the film grid (docs/semantics.md, "The film grid"): mouth and eye curves are
// sampled on the grid, converted there (mouth holds and blink holds count grid frames), and
// brought back to the source rate: a repainted stretch shows its grid drawings, each from
// its exact grid time; every other frame keeps its input value.
#ifndef KOMA_CORE_LIP_BLINK_GRID_H_
#define KOMA_CORE_LIP_BLINK_GRID_H_

#include <vector>

#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"

namespace koma {

// The curve at grid frames 0 .. grid_frames - 1 (grid frame g at source time
// grid.SourceTime(g), evaluated with motion3.json's rules; dense curves linear between
// samples).
std::vector<double> SampleOnGrid(const Curve& curve, const FilmGrid& grid, int grid_frames,
                                 bool beziers_restricted);

// Source-frame intervals [begin, end) on the grid: each end snapped to its nearest grid frame
// (within [0, grid_frames]); intervals that become empty are dropped. Sorted, disjoint input
// gives sorted, disjoint output.
std::vector<FrameInterval> IntervalsOnGrid(const std::vector<FrameInterval>& intervals,
                                           const FilmGrid& grid, int grid_frames);

// Grid frames a conversion repaints: inside the speech intervals (mouth), or from each
// blink's closing_begin to where its repaint ends (eyes).
std::vector<bool> SpeechMask(const std::vector<FrameInterval>& speech, int grid_frames);
std::vector<bool> BlinkMask(const std::vector<Blink>& blinks, int grid_frames);

struct SourceRateCurve {
  std::vector<double> values;     // per source frame
  std::vector<CurvePoint> steps;  // stepped keyframes, times in (fractional) source frames
};

// Source frame k shows grid_values[g] where g = grid.GridFrameOf(k) is repainted or is the
// grid frame just before a repainted run (whose source frames would otherwise show the
// in-between values the conversion removed), else source_values[k]. The stepped keys change at the
// exact time of a repainted grid frame, and at a source frame elsewhere; a point at frame 0, one at
// each change, one at the last source frame.
SourceRateCurve ExpandConverted(const std::vector<double>& grid_values,
                                const std::vector<bool>& repainted,
                                const std::vector<double>& source_values, const FilmGrid& grid);

// Per source frame (of `frames`): whether it shows a repainted grid frame in ExpandConverted
// (the runs, and the grid frame just before each).
std::vector<bool> RepaintedSourceFrames(const std::vector<bool>& repainted_runs,
                                        const FilmGrid& grid, int frames);

// A LipBlink curve inside a stepped timing group (docs/semantics.md, "Group modes"): per
// source frame k the input `source` at the source frame nearest its drawing's source time
// tau[k] (the group's timing), kept inside the run of frames around k that no conversion
// repainted, so a drawing that starts inside speech or a blink never shows the input's
// in-between values from there, and a flat stretch stays exactly its input. Repainted frames
// are 0 (the caller puts the conversion's values there).
std::vector<double> HeldBetweenRepaints(const std::vector<double>& source,
                                        const std::vector<double>& tau,
                                        const std::vector<bool>& repainted);

}  // namespace koma

#endif  // KOMA_CORE_LIP_BLINK_GRID_H_

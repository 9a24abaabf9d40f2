// --timing-from for `koma curves` and `koma lipblink`: an edited XDTS (the sheet --xdts
// wrote) mapped back to the drawings of koma's own answer for the same input and options,
// `computed` (docs/usage.md, "Timing from an edited sheet": why a second call and no sidecar).
#ifndef KOMA_CLIENT_TIMING_FROM_CURVES_H_
#define KOMA_CLIENT_TIMING_FROM_CURVES_H_

#include <string>
#include <vector>

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

// RetimeCurves: one sheet track per track of CurvesXdtsSheet(computed, name) (a timing
// group's timing); cell n of a track is that timing's drawing n, given as its tau
// (DrawingTiming.drawing_source_frame[n - 1]) at every counted frame of the row, in
// request->given_timings for the group. The sheet has every counted frame. A track of a
// --curve-on timing (not a group's own) cannot be given: INVALID_ARGUMENT naming it.
absl::Status SetCurvesTimingFrom(const std::string& path, const std::string& name,
                                 const v1::RetimeCurvesResponse& computed,
                                 v1::RetimeCurvesRequest* request,
                                 std::vector<std::string>* warnings);

// LipBlink: the mouth and eye tracks of LipBlinkXdtsSheet(computed, source_fps, name). A
// mouth track's runs of equal cells are holds of its curves (1 closed, 2 mid, 3 open) over
// the whole clip; an eye track's runs of non-open cells are blinks: c >= 1 closed (3) rows
// then h = 1..3 half (2) rows with h <= c, painted as koma paints a blink of hold h. Another
// run is INVALID_ARGUMENT naming track, frame and cells.
absl::Status SetLipBlinkTimingFrom(const std::string& path, const std::string& name,
                                   double source_fps, const v1::LipBlinkResponse& computed,
                                   v1::LipBlinkRequest* request,
                                   std::vector<std::string>* warnings);

}  // namespace koma::client

#endif  // KOMA_CLIENT_TIMING_FROM_CURVES_H_

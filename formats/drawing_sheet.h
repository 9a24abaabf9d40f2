// The drawing sheet CSV written by `koma curves --timing`: which drawing each output frame
// shows and the source time it samples.
#ifndef KOMA_FORMATS_DRAWING_SHEET_H_
#define KOMA_FORMATS_DRAWING_SHEET_H_

#include <string>
#include <vector>

#include "core/koma_uchi.h"

namespace koma::formats {

// Header `output_frame,drawing,source_frame,time_s`, one row per output frame t:
//   t, timing.drawing_of_frame[t], timing.source_frame[t] (FormatDouble, frames),
//   t / fps (printf "%.10g", seconds).
// "\n" line endings. Requires drawing_of_frame and source_frame of equal length, fps > 0.
std::string WriteDrawingSheetCsv(const DrawingTiming& timing, double fps);

// One track of a drawing sheet with timing groups: a group's name and timing.
struct DrawingSheetTrack {
  std::string name;
  const DrawingTiming* timing = nullptr;
};

// With timing groups, one track per group: the first (the default group) in the columns above,
// then per further track `<name>_drawing,<name>_source_frame`, after time_s. Requires every
// timing of the same length; one track writes exactly WriteDrawingSheetCsv.
std::string WriteGroupedDrawingSheetCsv(const std::vector<DrawingSheetTrack>& tracks, double fps);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_DRAWING_SHEET_H_

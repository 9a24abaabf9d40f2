// The drawing sheet CSV written by `koma curves --timing`: which drawing each output frame
// shows and the source time it samples.
#ifndef KOMA_FORMATS_DRAWING_SHEET_H_
#define KOMA_FORMATS_DRAWING_SHEET_H_

#include <string>

#include "core/koma_uchi.h"

namespace koma::formats {

// Header `output_frame,drawing,source_frame,time_s`, one row per output frame t:
//   t, timing.drawing_of_frame[t], timing.source_frame[t] (FormatDouble, frames),
//   t / fps (printf "%.10g", seconds).
// "\n" line endings. Requires drawing_of_frame and source_frame of equal length, fps > 0.
std::string WriteDrawingSheetCsv(const DrawingTiming& timing, double fps);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_DRAWING_SHEET_H_

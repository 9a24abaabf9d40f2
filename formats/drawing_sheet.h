// The drawing sheet CSV written by `koma curves --timing`: which drawing each output frame
// shows and the source time it samples.
#ifndef KOMA_FORMATS_DRAWING_SHEET_H_
#define KOMA_FORMATS_DRAWING_SHEET_H_

#include <string>
#include <vector>

#include "core/koma_uchi.h"

namespace koma::formats {

// One track of a drawing sheet: a timing group's name and timing, and per drawing the ids of
// the curves whose keys it draws (docs/semantics.md, "Every key is drawn"; may be empty).
struct DrawingSheetTrack {
  std::string name;
  const DrawingTiming* timing = nullptr;
  std::vector<std::vector<std::string>> keys;
};

// Header `output_frame,drawing,source_frame,time_s,keys`, one row per output frame t:
//   t, timing.drawing_of_frame[t], timing.source_frame[t] (FormatDouble, frames),
//   t / fps (printf "%.10g", seconds), and on the first frame showing a drawing (or, for a
//   drawing no frame shows, the next frame) the ids of the curves whose keys it draws,
//   separated by ";" (the cell quoted as CSV needs when an id holds a comma or a quote).
// "\n" line endings. Requires drawing_of_frame and source_frame of equal length, fps > 0.
std::string WriteDrawingSheetCsv(const DrawingSheetTrack& track, double fps);

// With timing groups, one track per group: the first (the default group) in the columns above,
// then per further track `<name>_drawing,<name>_source_frame`, after time_s; `keys` last, the
// keys of every track's drawings. Requires every timing of the same length; one track writes
// exactly WriteDrawingSheetCsv.
std::string WriteGroupedDrawingSheetCsv(const std::vector<DrawingSheetTrack>& tracks, double fps);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_DRAWING_SHEET_H_

// A retiming result as a CSV timing sheet (an animator's exposure sheet, one row per output
// frame), for spreadsheets and plotting.
#ifndef KOMA_FORMATS_TIMING_SHEET_H_
#define KOMA_FORMATS_TIMING_SHEET_H_

#include <string>
#include <string_view>
#include <vector>

#include "core/retime.h"

namespace koma::formats {

// "ORIGINAL", "DUPLICATE" or "HELD".
std::string_view FrameKindName(FrameKind kind);

// The header `output_frame,source_frame,kind,time_s` and one row per output frame t:
//   t,map.source_frames[t],FrameKindName(map.kinds[t]),t * frame_time (printf "%.10g")
// `frame_time` is in seconds per frame. Each time is one multiplication, never a running sum,
// so row 1000 carries no accumulated rounding. "\n" line endings, including after the last
// row. Requires map.kinds.size() == map.source_frames.size() (checked with assert only).
// With `grid_frames` (one per output frame, from a film-grid response) a fifth column
// `grid_frame` follows: the frame of the retimed 24 fps (timing_fps) sequence the row shows.
std::string WriteTimingSheetCsv(const TimingMap& map, double frame_time,
                                const std::vector<int32_t>* grid_frames = nullptr);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_TIMING_SHEET_H_

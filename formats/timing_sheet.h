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

// The rate a timing sheet's times are written on, frames per second: `timing_fps` (the film's
// rate; 0 = none) or else the nearest whole number of frames per second, when 1 / frame_time is
// within kSameRateTolerance of it (relative: the film grid's rule, core/film_grid.h), so a BVH
// Frame Time of 0.0416667 is 24 fps and 0.0083333 is 120; 0 when neither is (29.97 fps).
double RecognisedFps(double frame_time, double timing_fps);

// The header `output_frame,source_frame,kind,time_s` and one row per output frame t:
//   t,map.source_frames[t],FrameKindName(map.kinds[t]),time of t
// The time, in seconds, is t / recognised_fps when that is > 0 (RecognisedFps: "0.125" and
// "3" for frames 3 and 72 at 24 fps, the exact time on that rate, not 3 x a rounded Frame
// Time), written in the shortest form that reads back to the same double (FormatDouble);
// else t * frame_time printed with "%.10g" (10 significant digits: no binary noise such as
// 0.30000000000000004). Each time is one division or multiplication, never a running sum, so
// row 1000 carries no accumulated rounding. "\n" line endings, including after the last
// row. Requires map.kinds.size() == map.source_frames.size() (checked with assert only).
// With `grid_frames` (one per output frame, from a film-grid response) a fifth column
// `grid_frame` follows: the frame of the retimed 24 fps (timing_fps) sequence the row shows.
std::string WriteTimingSheetCsv(const TimingMap& map, double frame_time,
                                const std::vector<int32_t>* grid_frames = nullptr,
                                double recognised_fps = 0.0);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_TIMING_SHEET_H_

#include "formats/timing_sheet.h"

#include <cassert>
#include <cmath>
#include <cstddef>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "core/film_grid.h"
#include "formats/number_format.h"

namespace koma::formats {

std::string_view FrameKindName(FrameKind kind) {
  switch (kind) {
    case FrameKind::kOriginal:
      return "ORIGINAL";
    case FrameKind::kDuplicate:
      return "DUPLICATE";
    case FrameKind::kHeld:
      return "HELD";
  }
  return "UNKNOWN";  // not reached for a valid enum value
}

double RecognisedFps(double frame_time, double timing_fps) {
  if (!(frame_time > 0) || !std::isfinite(frame_time)) return 0.0;
  const double fps = 1.0 / frame_time;
  const auto same = [fps](double rate) {
    return rate > 0 && std::fabs(fps - rate) <= kSameRateTolerance * rate;
  };
  if (same(timing_fps)) return timing_fps;
  const double whole = std::nearbyint(fps);
  return same(whole) ? whole : 0.0;
}

std::string WriteTimingSheetCsv(const TimingMap& map, double frame_time,
                                const std::vector<int32_t>* grid_frames, double recognised_fps) {
  assert(map.kinds.size() == map.source_frames.size());
  assert(grid_frames == nullptr || grid_frames->size() == map.source_frames.size());
  std::string out = "output_frame,source_frame,kind,time_s";
  out.append(grid_frames != nullptr ? ",grid_frame\n" : "\n");
  for (size_t t = 0; t < map.source_frames.size(); ++t) {
    absl::StrAppend(&out, t, ",", map.source_frames[t], ",");
    out.append(FrameKindName(map.kinds[t]));  // std::string_view: no StrCat
    if (recognised_fps > 0) {
      // One correctly rounded IEEE division: the same bits everywhere.
      absl::StrAppend(&out, ",", FormatDouble(static_cast<double>(t) / recognised_fps));
    } else {
      // 10 significant digits: sub-microsecond up to 1000 s, and no binary noise such as
      // 0.6250005000000001 for 15 x 0.0416667 in a sheet people read.
      absl::StrAppend(&out, ",", absl::StrFormat("%.10g", static_cast<double>(t) * frame_time));
    }
    if (grid_frames != nullptr) absl::StrAppend(&out, ",", (*grid_frames)[t]);
    out.push_back('\n');
  }
  return out;
}

}  // namespace koma::formats

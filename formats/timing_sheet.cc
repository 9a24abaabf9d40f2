#include "formats/timing_sheet.h"

#include <cassert>
#include <cstddef>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

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

std::string WriteTimingSheetCsv(const TimingMap& map, double frame_time,
                                const std::vector<int32_t>* grid_frames) {
  assert(map.kinds.size() == map.source_frames.size());
  assert(grid_frames == nullptr || grid_frames->size() == map.source_frames.size());
  std::string out = "output_frame,source_frame,kind,time_s";
  out.append(grid_frames != nullptr ? ",grid_frame\n" : "\n");
  for (size_t t = 0; t < map.source_frames.size(); ++t) {
    const double time_s = static_cast<double>(t) * frame_time;
    absl::StrAppend(&out, t, ",", map.source_frames[t], ",");
    out.append(FrameKindName(map.kinds[t]));  // std::string_view: no StrCat
    // 10 significant digits: sub-microsecond up to 1000 s, and no binary noise such as
    // 0.6250005000000001 for 15 x 0.0416667 in a sheet people read.
    absl::StrAppend(&out, ",", absl::StrFormat("%.10g", time_s));
    if (grid_frames != nullptr) absl::StrAppend(&out, ",", (*grid_frames)[t]);
    out.push_back('\n');
  }
  return out;
}

}  // namespace koma::formats

#include "formats/drawing_sheet.h"

#include <cassert>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "formats/number_format.h"

namespace koma::formats {

std::string WriteDrawingSheetCsv(const DrawingTiming& timing, double fps) {
  assert(timing.drawing_of_frame.size() == timing.source_frame.size());
  std::string out = "output_frame,drawing,source_frame,time_s\n";
  for (size_t t = 0; t < timing.drawing_of_frame.size(); ++t) {
    absl::StrAppend(&out, t, ",", timing.drawing_of_frame[t], ",",
                    FormatDouble(timing.source_frame[t]), ",",
                    absl::StrFormat("%.10g", static_cast<double>(t) / fps), "\n");
  }
  return out;
}

std::string WriteGroupedDrawingSheetCsv(const std::vector<DrawingSheetTrack>& tracks, double fps) {
  assert(!tracks.empty());
  std::string out = "output_frame,drawing,source_frame,time_s";
  for (size_t k = 1; k < tracks.size(); ++k) {
    absl::StrAppend(&out, ",", tracks[k].name, "_drawing,", tracks[k].name, "_source_frame");
  }
  out += "\n";
  const DrawingTiming& first = *tracks[0].timing;
  for (size_t t = 0; t < first.drawing_of_frame.size(); ++t) {
    absl::StrAppend(&out, t, ",", first.drawing_of_frame[t], ",", FormatDouble(first.source_frame[t]),
                    ",", absl::StrFormat("%.10g", static_cast<double>(t) / fps));
    for (size_t k = 1; k < tracks.size(); ++k) {
      const DrawingTiming& timing = *tracks[k].timing;
      assert(timing.drawing_of_frame.size() == first.drawing_of_frame.size());
      absl::StrAppend(&out, ",", timing.drawing_of_frame[t], ",",
                      FormatDouble(timing.source_frame[t]));
    }
    out += "\n";
  }
  return out;
}

}  // namespace koma::formats

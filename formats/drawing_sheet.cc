#include "formats/drawing_sheet.h"

#include <cassert>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_replace.h"
#include "formats/number_format.h"

namespace koma::formats {

namespace {

// The CSV cell of a `keys` column: ids joined by ";", quoted when one holds a comma, a quote
// or a line break.
std::string KeysCell(const std::vector<std::string>& ids) {
  const std::string joined = absl::StrJoin(ids, ";");
  if (joined.find_first_of(",\"\r\n") == std::string::npos) return joined;
  return absl::StrCat("\"", absl::StrReplaceAll(joined, {{"\"", "\"\""}}), "\"");
}

// Per output frame of the tracks' timings: the ids of the keys drawn by the drawings that
// start showing there (a drawing no frame shows: at the next frame).
std::vector<std::vector<std::string>> KeysPerFrame(const std::vector<DrawingSheetTrack>& tracks,
                                                   size_t frames) {
  std::vector<std::vector<std::string>> per_frame(frames);
  for (const DrawingSheetTrack& track : tracks) {
    const std::vector<int>& of_frame = track.timing->drawing_of_frame;
    size_t t = 0;
    for (size_t d = 0; d < track.keys.size(); ++d) {
      while (t < frames && of_frame[t] < static_cast<int>(d)) ++t;
      if (t == frames) break;
      for (const std::string& id : track.keys[d]) per_frame[t].push_back(id);
    }
  }
  return per_frame;
}

}  // namespace

std::string WriteDrawingSheetCsv(const DrawingSheetTrack& track, double fps) {
  return WriteGroupedDrawingSheetCsv({track}, fps);
}

std::string WriteGroupedDrawingSheetCsv(const std::vector<DrawingSheetTrack>& tracks, double fps) {
  assert(!tracks.empty());
  std::string out = "output_frame,drawing,source_frame,time_s";
  for (size_t k = 1; k < tracks.size(); ++k) {
    absl::StrAppend(&out, ",", tracks[k].name, "_drawing,", tracks[k].name, "_source_frame");
  }
  out += ",keys\n";
  const DrawingTiming& first = *tracks[0].timing;
  assert(first.drawing_of_frame.size() == first.source_frame.size());
  const std::vector<std::vector<std::string>> keys =
      KeysPerFrame(tracks, first.drawing_of_frame.size());
  for (size_t t = 0; t < first.drawing_of_frame.size(); ++t) {
    absl::StrAppend(&out, t, ",", first.drawing_of_frame[t], ",", FormatDouble(first.source_frame[t]),
                    ",", absl::StrFormat("%.10g", static_cast<double>(t) / fps));
    for (size_t k = 1; k < tracks.size(); ++k) {
      const DrawingTiming& timing = *tracks[k].timing;
      assert(timing.drawing_of_frame.size() == first.drawing_of_frame.size());
      absl::StrAppend(&out, ",", timing.drawing_of_frame[t], ",",
                      FormatDouble(timing.source_frame[t]));
    }
    absl::StrAppend(&out, ",", KeysCell(keys[t]), "\n");
  }
  return out;
}

}  // namespace koma::formats

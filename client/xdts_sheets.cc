#include "client/xdts_sheets.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "convert/curves_convert.h"
#include "core/film_grid.h"
#include "formats/format_table.h"

namespace koma::client {
namespace {

using formats::XdtsCellTrack;
using formats::XdtsDialogLine;
using formats::XdtsDialogTrack;
using formats::XdtsSheet;

std::string BaseName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  // An input format's extension (formats/format_table.h), else a sheet's own (the fallback
  // is the -o or --xdts path).
  size_t extension = formats::FormatExtensionLength(base);
  for (const char* sheet : {".xdts", ".tsv"}) {
    if (extension == 0 && base.size() > std::strlen(sheet) &&
        absl::EndsWithIgnoreCase(base, sheet)) {
      extension = std::strlen(sheet);
    }
  }
  base.resize(base.size() - extension);
  return base;
}

// Index of the level nearest `value` among levels[0..2], ties to the lower index.
int NearestLevel(double value, const double (&levels)[3]) {
  int best = 0;
  for (int i = 1; i < 3; ++i) {
    const double d = value > levels[i] ? value - levels[i] : levels[i] - value;
    const double b = value > levels[best] ? value - levels[best] : levels[best] - value;
    if (d < b) best = i;
  }
  return best;
}

// Groups equal cell sequences: one track per distinct sequence, in order of first appearance,
// named by the ids that share it plus `legend`.
std::vector<XdtsCellTrack> GroupTracks(const std::vector<std::string>& ids,
                                       const std::vector<std::vector<std::string>>& cells,
                                       const std::string& legend) {
  std::vector<XdtsCellTrack> tracks;
  std::vector<std::vector<std::string>> names;
  for (size_t i = 0; i < ids.size(); ++i) {
    size_t t = 0;
    while (t < tracks.size() && tracks[t].cells != cells[i]) ++t;
    if (t == tracks.size()) {
      tracks.push_back({"", cells[i]});
      names.emplace_back();
    }
    names[t].push_back(ids[i]);
  }
  for (size_t t = 0; t < tracks.size(); ++t) {
    tracks[t].name = absl::StrCat(absl::StrJoin(names[t], ", "), " ", legend);
  }
  return tracks;
}

}  // namespace

std::vector<int> BlinkRows(const v1::EyeTrack& eye, int rows) {
  std::vector<int> out(static_cast<size_t>(rows), -1);
  const auto fill = [&](int from, int to, int drawing) {
    for (int r = std::max(from, 0); r < std::min(to, rows); ++r) out[r] = drawing;
  };
  for (int i = 0; i < eye.blinks_size(); ++i) {
    const v1::Blink& b = eye.blinks(i);
    const int limit = i + 1 < eye.blinks_size() ? eye.blinks(i + 1).closing_begin() : rows;
    const int closed_last = std::max(b.closed_end(), b.closed_begin() + b.hold() - 1);
    const int end = std::min(
        std::max(b.closed_end() + 1 + b.open_span(), closed_last + 1 + b.hold()), limit);
    const int closed_stop = std::min(end, closed_last + 1);
    const int mid_stop = std::min(end, closed_stop + b.hold());
    fill(b.closing_begin(), b.closed_begin(), 0);
    fill(b.closed_begin(), closed_stop, 2);
    fill(closed_stop, mid_stop, 1);
    fill(mid_stop, end, 0);
  }
  return out;
}

namespace {

// The layer of timing `t` (before its " (on N)"): with timing groups, its group's name, or
// "GROUP: ID, ..." for a timing of the group's curve overrides; without, `only` when it is the
// sheet's one track, else its curves' ids.
std::string CurvesTrackName(const v1::RetimeCurvesResponse& response, int t,
                            const std::vector<std::string>& ids, const std::string& only) {
  for (const v1::CurveTimingGroupResult& group : response.timing_groups()) {
    for (const int c : group.curves()) {
      if (c < 0 || c >= response.curves_size() || response.curves(c).timing() != t) continue;
      if (group.timing() == t) return group.name();
      return absl::StrCat(group.name(), ": ", absl::StrJoin(ids, ", "));
    }
  }
  return only.empty() ? absl::StrJoin(ids, ", ") : only;
}

}  // namespace

std::string XdtsClipName(const std::string& input, const std::string& fallback) {
  for (const std::string& path : {input, fallback}) {
    if (path.empty() || path == "-") continue;
    const std::string base = BaseName(path);
    if (!base.empty()) return base;
  }
  return "koma";
}

absl::StatusOr<XdtsSheet> SkeletalXdtsSheet(const v1::RetimeSkeletalResponse& response,
                                            const std::string& name) {
  const int frames = response.source_frames_size();
  if (frames == 0) return absl::InvalidArgumentError("the answer has no output frames");
  std::vector<int> shown;  // per row: the source frame it shows
  if (response.timing_fps() > 0 && response.grid_frames_size() == frames) {
    const int rows = *std::max_element(response.grid_frames().begin(),
                                       response.grid_frames().end()) + 1;
    shown.assign(static_cast<size_t>(rows), -1);
    for (int t = 0; t < frames; ++t) {
      int& row = shown[static_cast<size_t>(response.grid_frames(t))];
      if (row < 0) row = response.source_frames(t);
    }
    for (size_t r = 1; r < shown.size(); ++r) {
      if (shown[r] < 0) shown[r] = shown[r - 1];
    }
  } else {
    shown.assign(response.source_frames().begin(), response.source_frames().end());
  }
  XdtsSheet sheet;
  sheet.name = name;
  sheet.duration = static_cast<int>(shown.size());
  // Each cell is named after the source frame it shows, counted from 1, so an edited sheet
  // maps back to source frames by its cell ids alone (--timing-from): the ids are what
  // OpenToonz, CSP and TVPaint keep.
  std::vector<std::string> cells(shown.size());
  for (size_t r = 0; r < shown.size(); ++r) cells[r] = absl::StrCat(shown[r] + 1);
  sheet.cell_tracks.push_back({name, std::move(cells)});
  return sheet;
}

absl::StatusOr<XdtsSheet> CurvesXdtsSheet(const v1::RetimeCurvesResponse& response,
                                          const std::string& name) {
  std::vector<std::vector<std::string>> ids(static_cast<size_t>(response.timings_size()));
  for (const v1::RetimedCurve& curve : response.curves()) {
    if (curve.timing() >= 0 && curve.timing() < response.timings_size()) {
      ids[static_cast<size_t>(curve.timing())].push_back(curve.id());
    }
  }
  const bool grid = response.timing_fps() > 0;
  int rows = 0;
  for (int i = 0; i < response.timings_size(); ++i) {
    const v1::DrawingTiming& timing = response.timings(i);
    if (ids[i].empty()) continue;
    const int length = grid ? (timing.drawing_start_grid_size() > 0
                                   ? timing.drawing_start_grid(timing.drawing_start_grid_size() - 1) + 1
                                   : 0)
                            : timing.drawing_of_frame_size();
    rows = std::max(rows, length);
  }
  if (rows == 0) return absl::InvalidArgumentError("the answer times no curve");
  XdtsSheet sheet;
  sheet.name = name;
  sheet.duration = rows;
  int tracks = 0;
  for (const std::vector<std::string>& group : ids) tracks += group.empty() ? 0 : 1;
  for (int i = 0; i < response.timings_size(); ++i) {
    if (ids[i].empty()) continue;
    const v1::DrawingTiming& timing = response.timings(i);
    XdtsCellTrack track;
    track.name = absl::StrCat(CurvesTrackName(response, i, ids[i], tracks == 1 ? name : ""),
                              " (on ", timing.frames_per_drawing(), ")");
    track.cells.resize(static_cast<size_t>(rows));
    for (int r = 0; r < rows; ++r) {
      int drawing = 0;
      if (grid) {
        // The last drawing starting at or before grid frame r.
        const auto& starts = timing.drawing_start_grid();
        drawing = static_cast<int>(std::upper_bound(starts.begin(), starts.end(), r) -
                                   starts.begin()) - 1;
      } else {
        drawing = timing.drawing_of_frame(std::min(r, timing.drawing_of_frame_size() - 1));
      }
      track.cells[r] = absl::StrCat(std::max(drawing, 0) + 1);
    }
    // The key drawings (genga) of this track: a one-row dialog line where each drawing that
    // draws some curve's key starts, naming the curves (docs/semantics.md, "Every key is
    // drawn").
    const std::vector<std::vector<std::string>> keys = convert::KeysByDrawing(response, i);
    XdtsDialogTrack key_track{absl::StrCat(track.name, " keys"), {}};
    const auto& starts = grid ? timing.drawing_start_grid() : timing.drawing_start();
    for (int d = 0; d < starts.size() && static_cast<size_t>(d) < keys.size(); ++d) {
      const int begin = starts[d];
      if (keys[d].empty() || begin < 0 || begin >= rows) continue;
      key_track.lines.push_back({begin, begin + 1, "key", absl::StrJoin(keys[d], ", ")});
    }
    sheet.cell_tracks.push_back(std::move(track));
    if (!key_track.lines.empty()) sheet.dialog_tracks.push_back(std::move(key_track));
  }
  return sheet;
}

absl::StatusOr<XdtsSheet> LipBlinkXdtsSheet(const v1::LipBlinkResponse& response,
                                            double source_fps, const std::string& name) {
  if (response.curves_size() == 0) return absl::InvalidArgumentError("the answer has no curves");
  const int frames = response.curves(0).values_size();
  if (frames == 0) return absl::InvalidArgumentError("the answer's curves have no frames");
  std::optional<FilmGrid> grid;
  if (response.timing_fps() > 0) grid = FilmGrid::Make(source_fps, response.timing_fps());
  const int rows = grid ? grid->GridFrameCount(frames) : frames;
  std::vector<int> source_of_row(static_cast<size_t>(rows));
  for (int r = 0; r < rows; ++r) source_of_row[r] = grid ? grid->NearestSourceFrame(r, frames - 1) : r;
  std::map<std::string, const v1::ConvertedCurve*> curve_of;
  for (const v1::ConvertedCurve& curve : response.curves()) curve_of[curve.id()] = &curve;
  // Per row, the level nearest the converted value (0, 1, 2 in the order of `levels`).
  const auto nearest = [&](const std::string& id, const double (&levels)[3]) {
    std::vector<int> out(static_cast<size_t>(rows), 0);
    const auto it = curve_of.find(id);
    if (it == curve_of.end() || it->second->values_size() != frames) return out;
    for (int r = 0; r < rows; ++r) out[r] = NearestLevel(it->second->values(source_of_row[r]), levels);
    return out;
  };
  XdtsSheet sheet;
  sheet.name = name;
  sheet.duration = rows;

  std::vector<std::string> mouth_ids;
  std::vector<std::vector<std::string>> mouth_cells;
  for (const v1::MouthTrack& mouth : response.mouths()) {
    const double levels[3] = {mouth.closed_level(), mouth.mid_level(), mouth.open_level()};
    std::vector<int> shape = nearest(mouth.id(), levels);
    for (const v1::MouthHold& hold : mouth.holds()) {
      const int value = hold.shape() == v1::MOUTH_OPEN ? 2 : hold.shape() == v1::MOUTH_MID ? 1 : 0;
      for (int r = std::max(hold.begin(), 0); r < std::min(hold.begin() + hold.length(), rows); ++r) {
        shape[r] = value;
      }
    }
    std::vector<std::string> cells(static_cast<size_t>(rows));
    for (int r = 0; r < rows; ++r) cells[r] = absl::StrCat(shape[r] + 1);
    mouth_ids.push_back(mouth.id());
    mouth_cells.push_back(std::move(cells));
  }
  for (XdtsCellTrack& track : GroupTracks(mouth_ids, mouth_cells, "(1 closed, 2 mid, 3 open)")) {
    sheet.cell_tracks.push_back(std::move(track));
  }

  std::vector<std::string> eye_ids;
  std::vector<std::vector<std::string>> eye_cells;
  for (const v1::EyeTrack& eye : response.eyes()) {
    // In the sheet's order: open, half, closed.
    const double levels[3] = {eye.open_level(), eye.mid_level(), eye.closed_level()};
    std::vector<int> drawing = nearest(eye.id(), levels);
    const std::vector<int> painted = BlinkRows(eye, rows);
    std::vector<std::string> cells(static_cast<size_t>(rows));
    for (int r = 0; r < rows; ++r) cells[r] = absl::StrCat((painted[r] >= 0 ? painted[r] : drawing[r]) + 1);
    eye_ids.push_back(eye.id());
    eye_cells.push_back(std::move(cells));
  }
  for (XdtsCellTrack& track : GroupTracks(eye_ids, eye_cells, "(1 open, 2 half, 3 closed)")) {
    sheet.cell_tracks.push_back(std::move(track));
  }

  // Dialog: the mouths' speech intervals, one track per distinct list.
  std::vector<std::vector<std::string>> speakers;
  std::vector<std::vector<std::pair<int, int>>> speech_lists;
  for (const v1::MouthTrack& mouth : response.mouths()) {
    std::vector<std::pair<int, int>> speech;
    for (const v1::FrameInterval& i : mouth.speech()) {
      const int begin = std::max(i.begin(), 0), end = std::min(i.end(), rows);
      if (begin < end) speech.emplace_back(begin, end);
    }
    size_t t = 0;
    while (t < speech_lists.size() && speech_lists[t] != speech) ++t;
    if (t == speech_lists.size()) {
      speech_lists.push_back(speech);
      speakers.emplace_back();
    }
    speakers[t].push_back(mouth.id());
  }
  for (size_t t = 0; t < speech_lists.size(); ++t) {
    XdtsDialogTrack track;
    track.name = absl::StrCat(absl::StrJoin(speakers[t], ", "), " speech");
    for (size_t k = 0; k < speech_lists[t].size(); ++k) {
      track.lines.push_back(XdtsDialogLine{speech_lists[t][k].first, speech_lists[t][k].second,
                                           name, absl::StrCat("speech ", k + 1)});
    }
    sheet.dialog_tracks.push_back(std::move(track));
  }
  return sheet;
}

}  // namespace koma::client

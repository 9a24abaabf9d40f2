#include "client/timing_from_curves.h"

#include <algorithm>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/string_view.h"
#include "client/files.h"
#include "client/timing_from.h"
#include "client/xdts_sheets.h"
#include "formats/error_text.h"

namespace koma::client {
namespace {

// The legends LipBlinkXdtsSheet ends its track names with.
constexpr absl::string_view kMouthLegend = " (1 closed, 2 mid, 3 open)";
constexpr absl::string_view kEyeLegend = " (1 open, 2 half, 3 closed)";

// The timing group that timing `t` is the one timing of ("body" without timing groups).
absl::StatusOr<std::string> GroupOfTiming(const v1::RetimeCurvesResponse& computed, int t,
                                          const std::string& track) {
  for (const v1::CurveTimingGroupResult& group : computed.timing_groups()) {
    if (group.timing() == t) return group.name();
  }
  if (computed.timing_groups_size() == 0 && t == 0) return std::string("body");
  return absl::InvalidArgumentError(
      absl::StrCat("track ", formats::QuoteForError(track),
                   ": the timing of --curve-on curves cannot be given, only a timing group's own"));
}

absl::Status Prefixed(const std::string& path, const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat(InputName(path), ": ", status.message()));
}

// ReadSheetDrawings for a sheet of every counted frame, `rows` of them (on the timing_fps grid
// when > 0).
absl::StatusOr<std::vector<std::vector<int>>> ReadKomaSheet(
    const std::string& path, const std::vector<KomaSheetTrack>& tracks, int rows, double timing_fps,
    std::vector<std::string>* warnings, formats::SheetKind csv) {
  return ReadSheetDrawings(
      path, tracks, rows, false,
      timing_fps > 0 ? absl::StrCat(" on the ", timing_fps, " fps grid") : std::string(), warnings,
      csv);
}

// The rows of one run of non-open eye cells [begin, end) (1 half, 2 closed) as a blink.
absl::StatusOr<v1::Blink> BlinkOfRun(const std::vector<int>& cells, int begin, int end,
                                     const std::string& track) {
  int closed_end = begin;
  while (closed_end < end && cells[static_cast<size_t>(closed_end)] == 2) ++closed_end;
  int half_end = closed_end;
  while (half_end < end && cells[static_cast<size_t>(half_end)] == 1) ++half_end;
  const int closed = closed_end - begin, half = half_end - closed_end;
  if (closed == 0 || half_end != end || half < 1 || half > 3 || half > closed) {
    std::string shown;
    for (int r = begin; r < end; ++r) absl::StrAppend(&shown, cells[static_cast<size_t>(r)] + 1);
    return absl::InvalidArgumentError(absl::StrCat(
        "track ", formats::QuoteForError(track), ", frame ", begin + 1, ": cells ", shown,
        " are no blink koma paints: a blink is closed (3) for c frames, then half (2) for 1 "
        "to 3 frames, at most c, then open (1)"));
  }
  v1::Blink blink;
  blink.set_closing_begin(begin);
  blink.set_closed_begin(begin);
  blink.set_closed_end(closed_end - 1);
  blink.set_hold(half);
  blink.set_open_span(0);
  return blink;
}

// A mouth's holds from its track's cells: runs of equal cells (1 closed, 2 mid, 3 open) over
// the rows of koma's speech and the rows the animator changed; elsewhere the mouth keeps its
// input, as koma's answer did (those rows show the input's nearest level).
v1::GivenMouthTiming MouthFromCells(const v1::MouthTrack& computed, const std::vector<int>& cells,
                                    const std::vector<int>& unedited) {
  const int rows = static_cast<int>(cells.size());
  std::vector<bool> held(cells.size(), false);
  for (const v1::FrameInterval& speech : computed.speech()) {
    for (int r = std::max(speech.begin(), 0); r < std::min(speech.end(), rows); ++r) held[r] = true;
  }
  for (int r = 0; r < rows; ++r) held[r] = held[r] || cells[r] != unedited[r];
  v1::GivenMouthTiming mouth;
  mouth.set_id(computed.id());
  for (int r = 0; r < rows;) {
    if (!held[r]) {
      ++r;
      continue;
    }
    int end = r;
    while (end < rows && held[end] && cells[end] == cells[r]) ++end;
    v1::MouthHold* hold = mouth.add_holds();
    hold->set_begin(r);
    hold->set_length(end - r);
    // Cells 1, 2, 3 are MOUTH_CLOSED, MOUTH_MID, MOUTH_OPEN (1, 2, 3).
    hold->set_shape(static_cast<v1::MouthShape>(cells[r] + 1));
    r = end;
  }
  return mouth;
}

// An eye's blinks from its track's cells (0 open, 1 half, 2 closed): koma's own blink where
// the rows it paints are unchanged; else each run of non-open cells a blink (BlinkOfRun),
// reaching back and forward over the open cells koma painted open next to it, so they stay
// painted open rather than showing the input.
absl::StatusOr<v1::GivenEyeTiming> EyeFromCells(const v1::EyeTrack& computed,
                                                const std::vector<int>& cells,
                                                const std::vector<int>& unedited,
                                                const std::string& track) {
  const int rows = static_cast<int>(cells.size());
  const std::vector<int> painted = BlinkRows(computed, rows);
  std::vector<bool> kept(cells.size(), false);  // rows of a kept computed blink
  std::vector<v1::Blink> blinks;
  for (int i = 0; i < computed.blinks_size(); ++i) {
    const v1::Blink& blink = computed.blinks(i);
    const int limit =
        i + 1 < computed.blinks_size() ? computed.blinks(i + 1).closing_begin() : rows;
    int end = std::max(blink.closed_begin(), 0);
    while (end < std::min(limit, rows) && painted[end] >= 0) ++end;
    bool same = true;
    for (int r = std::max(blink.closing_begin(), 0); r < end; ++r)
      same = same && cells[r] == unedited[r];
    if (!same) continue;
    for (int r = std::max(blink.closing_begin(), 0); r < end; ++r) kept[r] = true;
    blinks.push_back(blink);
  }
  for (int r = 0; r < rows;) {
    if (cells[r] == 0 || kept[r]) {
      ++r;
      continue;
    }
    int end = r;
    while (end < rows && cells[end] != 0 && !kept[end]) ++end;
    absl::StatusOr<v1::Blink> blink = BlinkOfRun(cells, r, end, track);
    if (!blink.ok()) return blink.status();
    int before = r;
    while (before > 0 && cells[before - 1] == 0 && painted[before - 1] >= 0 && !kept[before - 1])
      --before;
    int after = end;
    while (after < rows && cells[after] == 0 && painted[after] >= 0 && !kept[after]) ++after;
    blink->set_closing_begin(before);
    blink->set_open_span(std::max(0, after - 1 - blink->closed_end()));
    blinks.push_back(*blink);
    r = end;
  }
  std::sort(blinks.begin(), blinks.end(), [](const v1::Blink& a, const v1::Blink& b) {
    return a.closed_begin() < b.closed_begin();
  });
  v1::GivenEyeTiming eye;
  eye.set_id(computed.id());
  for (const v1::Blink& blink : blinks) *eye.add_blinks() = blink;
  return eye;
}

}  // namespace

absl::Status SetCurvesTimingFrom(const std::string& path, const std::string& name,
                                 const v1::RetimeCurvesResponse& computed,
                                 v1::RetimeCurvesRequest* request,
                                 std::vector<std::string>* warnings) {
  absl::StatusOr<formats::XdtsSheet> sheet = CurvesXdtsSheet(computed, name);
  if (!sheet.ok()) return sheet.status();
  // CurvesXdtsSheet's tracks: the timings that time a curve, in order.
  std::vector<int> timing_of_track;
  for (int t = 0; t < computed.timings_size(); ++t) {
    for (const v1::RetimedCurve& curve : computed.curves()) {
      if (curve.timing() == t) {
        timing_of_track.push_back(t);
        break;
      }
    }
  }
  std::vector<KomaSheetTrack> tracks;
  std::vector<std::string> groups;
  for (size_t k = 0; k < timing_of_track.size(); ++k) {
    const std::string& track = sheet->cell_tracks[k].name;
    const v1::DrawingTiming& timing = computed.timings(timing_of_track[k]);
    absl::StatusOr<std::string> group = GroupOfTiming(computed, timing_of_track[k], track);
    if (!group.ok()) return Prefixed(path, group.status());
    groups.push_back(*group);
    // The drawing sheet CSV names its first group's columns `drawing`, a further group G's
    // `G_drawing` (curves_command's --timing writer: groups with drawings, in order).
    int first_csv_timing = 0;
    for (int g = computed.timing_groups_size() - 1; g >= 0; --g) {
      const v1::CurveTimingGroupResult& result = computed.timing_groups(g);
      if (result.curves_size() > 0 && result.frames_per_drawing() != 0)
        first_csv_timing = result.timing();
    }
    const bool first_csv_track = timing_of_track[k] == first_csv_timing;
    tracks.push_back({track, timing.drawing_source_frame_size(),
                      absl::StrCat("its drawings 1 to ", timing.drawing_source_frame_size()),
                      first_csv_track ? std::string("drawing") : *group + "_drawing",
                      {timing.drawing_source_frame().begin(), timing.drawing_source_frame().end()}});
  }
  absl::StatusOr<std::vector<std::vector<int>>> drawings =
      ReadKomaSheet(path, tracks, sheet->duration, computed.timing_fps(), warnings,
                    formats::SheetKind::kDrawingCsv);
  if (!drawings.ok()) return drawings.status();
  for (size_t k = 0; k < tracks.size(); ++k) {
    const v1::DrawingTiming& timing = computed.timings(timing_of_track[k]);
    v1::GivenDrawingTiming* given = request->add_given_timings();
    given->set_group(groups[k]);
    std::vector<int> unedited;  // the drawings koma wrote, 0-based
    for (const std::string& cell : sheet->cell_tracks[k].cells)
      unedited.push_back(std::stoi(cell) - 1);
    // An edited track shows each drawing at its tau exactly: the keys koma draws on the drawing
    // whose hold contains them would land on whatever drawing the animator moved there.
    given->set_exact_taus((*drawings)[k] != unedited);
    for (const int d : (*drawings)[k]) given->add_source_frame(timing.drawing_source_frame(d));
  }
  return absl::OkStatus();
}

absl::Status SetLipBlinkTimingFrom(const std::string& path, const std::string& name,
                                   double source_fps, const v1::LipBlinkResponse& computed,
                                   v1::LipBlinkRequest* request,
                                   std::vector<std::string>* warnings) {
  absl::StatusOr<formats::XdtsSheet> sheet = LipBlinkXdtsSheet(computed, source_fps, name);
  if (!sheet.ok()) return sheet.status();
  std::vector<KomaSheetTrack> tracks;
  for (const formats::XdtsCellTrack& track : sheet->cell_tracks) {
    tracks.push_back({track.name, 3, "1 to 3"});
  }
  absl::StatusOr<std::vector<std::vector<int>>> drawings =
      ReadKomaSheet(path, tracks, sheet->duration, computed.timing_fps(), warnings,
                    formats::SheetKind::kXdts);
  if (!drawings.ok()) return drawings.status();
  v1::GivenLipBlinkTiming* given = request->mutable_given_timing();
  for (size_t k = 0; k < tracks.size(); ++k) {
    const std::string& track = tracks[k].name;
    const std::vector<int>& cells = (*drawings)[k];
    std::vector<int> unedited;  // the cells koma wrote
    for (const std::string& cell : sheet->cell_tracks[k].cells) {
      unedited.push_back(cell[0] - '1');
    }
    // The track's curves: its name is "ID, ID, ... LEGEND" (LipBlinkXdtsSheet's GroupTracks).
    const bool mouth = absl::EndsWith(track, kMouthLegend);
    const absl::string_view ids = absl::string_view(track).substr(
        0, track.size() - (mouth ? kMouthLegend : kEyeLegend).size());
    for (const absl::string_view id : absl::StrSplit(ids, ", ")) {
      if (mouth) {
        for (const v1::MouthTrack& m : computed.mouths()) {
          if (m.id() == id) *given->add_mouths() = MouthFromCells(m, cells, unedited);
        }
        continue;
      }
      for (const v1::EyeTrack& e : computed.eyes()) {
        if (e.id() != id) continue;
        absl::StatusOr<v1::GivenEyeTiming> eye = EyeFromCells(e, cells, unedited, track);
        if (!eye.ok()) return Prefixed(path, eye.status());
        *given->add_eyes() = *std::move(eye);
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace koma::client

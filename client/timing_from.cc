#include "client/timing_from.h"

#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "client/files.h"
#include "client/xdts_sheets.h"
#include "core/film_grid.h"
#include "formats/error_text.h"
#include "formats/xdts.h"

namespace koma::client {
namespace {

bool LooksLikeXdts(const std::string& path, std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return text.substr(0, std::strlen(formats::kXdtsIdentifier)) == formats::kXdtsIdentifier ||
         absl::EndsWithIgnoreCase(path, ".xdts");
}

absl::Status Prefixed(const std::string& path, const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat(InputName(path), ": ", status.message()));
}

}  // namespace

absl::StatusOr<formats::SheetTiming> ReadTimingFrom(const std::string& path) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  absl::StatusOr<formats::SheetTiming> sheet = LooksLikeXdts(path, *text)
                                                   ? formats::ReadSheetTimingXdts(*text)
                                                   : formats::ReadSheetTimingCsv(*text);
  if (!sheet.ok()) return Prefixed(path, sheet.status());
  for (std::string& warning : sheet->warnings) warning.insert(0, InputName(path) + ": ");
  return sheet;
}

absl::StatusOr<std::vector<std::vector<int>>> ReadSheetDrawings(
    const std::string& path, const std::vector<KomaSheetTrack>& tracks, int counted,
    bool shorter_ok, const std::string& counted_note, std::vector<std::string>* warnings,
    formats::SheetKind csv) {
  absl::StatusOr<formats::SheetTiming> sheet = ReadTimingFrom(path);
  if (!sheet.ok()) return sheet.status();
  if (sheet->kind != formats::SheetKind::kXdts && sheet->kind != csv) {
    const bool drawings = sheet->kind == formats::SheetKind::kDrawingCsv;
    return absl::InvalidArgumentError(absl::StrCat(
        InputName(path), ": ",
        drawings ? "a drawing sheet CSV (koma curves --timing: a drawing column)"
                 : "a source frame timing CSV (koma skeletal --timing: no drawing column)",
        csv == formats::SheetKind::kXdts
            ? "; this command reads only an XDTS sheet (--xdts)"
            : csv == formats::SheetKind::kDrawingCsv
                  ? "; koma curves reads its drawing sheet (--timing) or an XDTS (--xdts)"
                  : "; koma skeletal reads its timing CSV (--timing) or an XDTS (--xdts)"));
  }
  const bool drawing_csv = sheet->kind == formats::SheetKind::kDrawingCsv;
  if (drawing_csv && !counted_note.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        InputName(path), ": a drawing sheet CSV has a row per output frame and this answer is "
        "timed", counted_note, ": apply the XDTS (--xdts) instead, or write and apply the CSV "
        "with --timing-fps 0"));
  }
  std::vector<std::string> names;
  for (const KomaSheetTrack& track : tracks) names.push_back(drawing_csv ? track.csv_name : track.name);
  absl::StatusOr<std::vector<int>> match = formats::MatchSheetTracks(*sheet, names);
  if (!match.ok()) return Prefixed(path, match.status());
  std::vector<std::vector<int>> out;
  for (size_t t = 0; t < tracks.size(); ++t) {
    const formats::SheetTimingTrack& cells = sheet->tracks[static_cast<size_t>((*match)[t])];
    for (size_t r = 0; drawing_csv && r < cells.cells.size(); ++r) {
      // A drawing sheet names drawings from 0 (its cells are drawing + 1): say so in its terms.
      const std::string& cell = cells.cells[r];
      if (!cell.empty() && std::stoll(cell) > tracks[t].drawings) {
        return absl::InvalidArgumentError(absl::StrCat(
            InputName(path), ": line ", cells.lines[r], ": track ",
            formats::QuoteForError(cells.name), ", frame ", r + 1, ": drawing ",
            std::stoll(cell) - 1, " names no drawing (the drawings are 0 to ",
            tracks[t].drawings - 1, ")"));
      }
    }
    absl::StatusOr<std::vector<int>> drawings =
        formats::SheetDrawings(cells, tracks[t].drawings, tracks[t].what);
    if (!drawings.ok()) return Prefixed(path, drawings.status());
    const int rows = static_cast<int>(drawings->size());
    if (counted > 0 && (rows > counted || (rows < counted && !shorter_ok))) {
      const std::string where =
          rows > counted
              ? absl::StrCat(", frame ", counted + 1, ": cell ",
                             formats::QuoteForError(cells.cells[static_cast<size_t>(counted)]),
                             " is past the clip's end")
              : absl::StrCat(", frame ", rows, ": the sheet ends before the clip");
      return absl::InvalidArgumentError(absl::StrCat(
          InputName(path), ": track ", formats::QuoteForError(cells.name), where,
          ": the sheet has ", rows, " frames, the clip ", counted, counted_note,
          shorter_ok ? " (a sheet may be shorter, not longer)" : " (a sheet has every frame)"));
    }
    for (size_t r = 0; r < cells.stated_source_frames.size() && !tracks[t].taus.empty(); ++r) {
      const std::string& stated = cells.stated_source_frames[r];
      const double tau = tracks[t].taus[static_cast<size_t>((*drawings)[r])];
      double value = 0;
      if (stated.empty()) continue;
      if (!absl::SimpleAtod(stated, &value) || !(std::abs(value - tau) <= kStatedTauTolerance)) {
        return absl::InvalidArgumentError(absl::StrCat(
            InputName(path), ": line ", cells.lines[r], ": track ",
            formats::QuoteForError(cells.name), ", frame ", r + 1, ": drawing ",
            (*drawings)[r], " is source frame ", tau, ", the row's source_frame says ",
            formats::QuoteForError(stated),
            " (koma reads the drawing column: change the drawing, or clear source_frame)"));
      }
    }
    out.push_back(*std::move(drawings));
  }
  for (std::string& warning : sheet->warnings) {
    if (warnings != nullptr) {
      warnings->push_back(std::move(warning));
    } else {
      std::cerr << "koma: warning: " << warning << "\n";
    }
  }
  return out;
}

absl::Status SetSkeletalTimingFrom(const std::string& path, const std::string& track,
                                   const SkeletalClipShape& clip,
                                   v1::RetimeSkeletalRequest* request,
                                   std::vector<std::string>* warnings) {
  // Without the clip's frame count (a file the server reads) any cell number passes here and
  // the server names the one past the clip (given_timing.source_frames[i]).
  const int drawings = clip.frame_count > 0 ? clip.frame_count : 1 << 30;
  const std::string what = clip.frame_count > 0
                               ? absl::StrCat("the clip's source frames 1 to ", clip.frame_count)
                               : "source frames from 1";
  int counted = 0;
  std::string note;
  if (clip.frame_count > 0) {
    const double timing_fps = clip.timing_fps.value_or(kDefaultTimingFps);
    const std::optional<FilmGrid> grid = FilmGrid::Make(clip.source_fps, timing_fps);
    counted = grid ? grid->GridFrameCount(clip.frame_count) : clip.frame_count;
    if (grid) note = absl::StrCat(" on the ", timing_fps, " fps grid");
  }
  absl::StatusOr<std::vector<std::vector<int>>> frames =
      ReadSheetDrawings(path, {{track, drawings, what}}, counted, true, note, warnings);
  if (!frames.ok()) return frames.status();
  const std::vector<int>& shown = (*frames)[0];
  request->mutable_given_timing()->mutable_source_frames()->Add(shown.begin(), shown.end());
  return absl::OkStatus();
}

absl::StatusOr<std::string> TimingFromFor(const std::string& timing_from,
                                          const std::string& input) {
  struct stat info;
  if (IsStdio(timing_from) || ::stat(timing_from.c_str(), &info) != 0 || !S_ISDIR(info.st_mode)) {
    return timing_from;
  }
  const std::string folder =
      !timing_from.empty() && timing_from.back() == '/' ? timing_from : timing_from + "/";
  const std::string name = XdtsClipName(input, "");
  for (const char* extension : {".xdts", ".timing.csv"}) {
    const std::string path = folder + name + extension;
    if (::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode)) return path;
  }
  return absl::NotFoundError(absl::StrCat("--timing-from ", timing_from, ": no sheet for ",
                                          InputName(input), " (", folder, name, ".xdts or ", folder,
                                          name, ".timing.csv)"));
}

}  // namespace koma::client

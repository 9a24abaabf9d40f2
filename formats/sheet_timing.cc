#include "formats/sheet_timing.h"

#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_replace.h"
#include "absl/strings/str_split.h"
#include "core/status_macros.h"
#include "formats/error_text.h"

namespace koma::formats {
namespace {

std::string TrackLabel(const std::string& name) {
  return absl::StrCat("track ", QuoteForError(name));
}

// One CSV line split on commas, each value trimmed of spaces and unquoted (and the line of
// its CR). A quoted comma is not kept together: the columns koma reads come before `keys`.
std::vector<std::string> CsvValues(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string> values;
  for (absl::string_view value : absl::StrSplit(absl::string_view(line.data(), line.size()), ',')) {
    value = absl::StripAsciiWhitespace(value);
    // A spreadsheet may quote a cell ("12"): read without its quotes, "" inside as one.
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
      values.push_back(absl::StrReplaceAll(value.substr(1, value.size() - 2), {{"\"\"", "\""}}));
      continue;
    }
    values.emplace_back(value);
  }
  return values;
}

bool IsBlankLine(std::string_view line) {
  for (const char c : line) {
    if (c != ' ' && c != '\t' && c != '\r' && c != ',') return false;
  }
  return true;
}

// A whole number >= 0 of at most 9 digits (so it fits an int), or an error naming the line.
absl::StatusOr<int> CsvCount(const std::string& value, int line, const char* column) {
  int number = 0;
  if (value.empty() || value.size() > 9 ||
      value.find_first_not_of("0123456789") != std::string::npos ||
      !absl::SimpleAtoi(value, &number)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "line ", line, ": ", column, " ", QuoteForError(value), " is not a whole number >= 0"));
  }
  return number;
}

// `koma curves --timing`'s drawing sheet (ReadSheetTimingCsv): lines[first] is its header.
absl::StatusOr<SheetTiming> ReadDrawingSheetCsv(const std::vector<std::string_view>& lines,
                                                size_t first, int max_rows) {
  const std::vector<std::string> header = CsvValues(lines[first]);
  struct Column {
    int drawing = -1, source = -1;
  };
  SheetTiming sheet;
  sheet.kind = SheetKind::kDrawingCsv;
  std::vector<Column> columns;
  for (size_t c = 0; c < header.size(); ++c) {
    const std::string& name = header[c];
    constexpr absl::string_view kSuffix = "_drawing";
    if (name == "drawing" || (name.size() > kSuffix.size() && absl::EndsWith(name, kSuffix))) {
      const std::string group = name == "drawing" ? "" : name.substr(0, name.size() - kSuffix.size());
      Column column{static_cast<int>(c), -1};
      const std::string source = group.empty() ? "source_frame" : group + "_source_frame";
      for (size_t s = 0; s < header.size(); ++s) {
        if (header[s] == source) column.source = static_cast<int>(s);
      }
      columns.push_back(column);
      sheet.tracks.push_back({name, {}, {}, {}});
    }
  }
  for (size_t l = first + 1; l < lines.size(); ++l) {
    if (IsBlankLine(lines[l])) continue;
    const int line = static_cast<int>(l) + 1;
    if (static_cast<int>(sheet.rows) >= max_rows) {
      return absl::InvalidArgumentError(absl::StrCat("line ", line, ": more than ", max_rows, " rows"));
    }
    const std::vector<std::string> values = CsvValues(lines[l]);
    const auto value = [&](int column) {
      return column >= 0 && static_cast<size_t>(column) < values.size() ? values[column]
                                                                        : std::string();
    };
    for (size_t k = 0; k < columns.size(); ++k) {
      SheetTimingTrack& track = sheet.tracks[k];
      std::string cell;
      if (!value(columns[k].drawing).empty()) {
        KOMA_ASSIGN_OR_RETURN(const int drawing,
                              CsvCount(value(columns[k].drawing), line, header[columns[k].drawing].c_str()));
        cell = absl::StrCat(static_cast<long long>(drawing) + 1);
      }
      track.cells.push_back(std::move(cell));
      track.lines.push_back(line);
      track.stated_source_frames.push_back(value(columns[k].source));
    }
    ++sheet.rows;
  }
  if (sheet.rows == 0) {
    return absl::InvalidArgumentError(absl::StrCat("no rows after the header on line ", first + 1));
  }
  return sheet;
}

}  // namespace

absl::StatusOr<SheetTiming> ReadSheetTimingXdts(std::string_view text,
                                                const XdtsReadLimits& limits) {
  KOMA_ASSIGN_OR_RETURN(XdtsSheet xdts, ReadXdts(text, limits));
  SheetTiming sheet;
  sheet.rows = xdts.duration;
  for (XdtsCellTrack& track : xdts.cell_tracks) {
    sheet.tracks.push_back({std::move(track.name), std::move(track.cells)});
  }
  if (xdts.ignored_time_tables > 0) {
    sheet.warnings.push_back(absl::StrCat(
        xdts.ignored_time_tables, " extra time table", xdts.ignored_time_tables == 1 ? "" : "s",
        " ignored: koma reads the first (", QuoteForError(xdts.name), ")"));
  }
  return sheet;
}

absl::StatusOr<SheetTiming> ReadSheetTimingCsv(std::string_view text, int max_rows) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<std::string_view> lines;
  for (size_t start = 0; start < text.size();) {
    const size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string_view::npos ? end : end - start));
    start = end == std::string_view::npos ? text.size() : end + 1;
  }
  size_t first = 0;
  while (first < lines.size() && IsBlankLine(lines[first])) ++first;
  if (first == lines.size()) return absl::InvalidArgumentError("no header line: the file is empty");
  const std::vector<std::string> header = CsvValues(lines[first]);
  for (const std::string& name : header) {
    if (name == "drawing") return ReadDrawingSheetCsv(lines, first, max_rows);
  }
  int source_column = -1, grid_column = -1;
  for (size_t c = 0; c < header.size(); ++c) {
    if (header[c] == "source_frame") source_column = static_cast<int>(c);
    if (header[c] == "grid_frame") grid_column = static_cast<int>(c);
  }
  if (source_column < 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "line ", first + 1, ": no source_frame column in the header ", QuoteForError(lines[first]),
        " (koma's --timing sheet: "
        "output_frame,source_frame,kind,time_s[,grid_frame])"));
  }
  SheetTimingTrack track;
  int previous_grid = -1;
  for (size_t l = first + 1; l < lines.size(); ++l) {
    if (IsBlankLine(lines[l])) continue;
    const int line = static_cast<int>(l) + 1;
    const std::vector<std::string> values = CsvValues(lines[l]);
    const auto value = [&](int column) {
      return static_cast<size_t>(column) < values.size() ? values[column] : std::string();
    };
    std::string cell;
    if (!value(source_column).empty()) {
      KOMA_ASSIGN_OR_RETURN(const int source, CsvCount(value(source_column), line, "source_frame"));
      cell = absl::StrCat(static_cast<long long>(source) + 1);
    }
    if (grid_column < 0) {
      if (static_cast<int>(track.cells.size()) >= max_rows) {
        return absl::InvalidArgumentError(
            absl::StrCat("line ", line, ": more than ", max_rows, " rows"));
      }
      track.cells.push_back(std::move(cell));
      continue;
    }
    KOMA_ASSIGN_OR_RETURN(const int grid, CsvCount(value(grid_column), line, "grid_frame"));
    if (grid >= max_rows) {
      return absl::InvalidArgumentError(
          absl::StrCat("line ", line, ": grid_frame ", grid, " must be < ", max_rows));
    }
    if (grid < previous_grid) {
      return absl::InvalidArgumentError(absl::StrCat("line ", line, ": grid_frame ", grid,
                                                     " comes after grid_frame ", previous_grid,
                                                     " (grid frames must not decrease)"));
    }
    if (grid == previous_grid) {
      std::string& row = track.cells.back();
      if (row.empty()) row = cell;  // a blank row of the grid frame takes a later one's cell
      if (!cell.empty() && cell != row) {
        return absl::InvalidArgumentError(absl::StrCat(
            "line ", line, ": grid_frame ", grid, " shows source_frame ", value(source_column),
            " here and a different one on a line before (one grid frame shows one drawing)"));
      }
      continue;
    }
    // Grid frames no line names repeat the one before (a source slower than the grid).
    const std::string before = track.cells.empty() ? std::string() : track.cells.back();
    while (static_cast<int>(track.cells.size()) < grid) track.cells.push_back(before);
    track.cells.push_back(std::move(cell));
    previous_grid = grid;
  }
  if (track.cells.empty()) {
    return absl::InvalidArgumentError(absl::StrCat("no rows after the header on line ", first + 1));
  }
  SheetTiming sheet;
  sheet.kind = SheetKind::kSourceFrameCsv;
  sheet.rows = static_cast<int>(track.cells.size());
  sheet.tracks.push_back(std::move(track));
  return sheet;
}

absl::StatusOr<std::vector<int>> MatchSheetTracks(const SheetTiming& sheet,
                                                  const std::vector<std::string>& koma_tracks) {
  std::vector<int> match(koma_tracks.size(), -1);
  std::vector<bool> taken(sheet.tracks.size(), false);
  for (size_t k = 0; k < koma_tracks.size(); ++k) {
    for (size_t s = 0; s < sheet.tracks.size(); ++s) {
      if (!taken[s] && sheet.tracks[s].name == koma_tracks[k]) {
        match[k] = static_cast<int>(s);
        taken[s] = true;
        break;
      }
    }
  }
  size_t next = 0;
  for (size_t k = 0; k < koma_tracks.size(); ++k) {
    if (match[k] >= 0) continue;
    while (next < taken.size() && taken[next]) ++next;
    if (next == taken.size()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "no track for ", QuoteForError(koma_tracks[k]), ": the sheet's ", sheet.tracks.size(),
          " Cell track", sheet.tracks.size() == 1 ? " is" : "s are",
          " taken by the clip's other tracks (tracks match by name, then by order)"));
    }
    match[k] = static_cast<int>(next);
    taken[next] = true;
  }
  for (size_t s = 0; s < taken.size(); ++s) {
    if (taken[s]) continue;
    std::vector<std::string> names;
    for (const std::string& name : koma_tracks) names.push_back(QuoteForError(name));
    return absl::InvalidArgumentError(absl::StrCat(
        TrackLabel(sheet.tracks[s].name), " (Cell track ", s + 1, " of ", sheet.tracks.size(),
        "): no such track: the clip's tracks are ", absl::StrJoin(names, ", ")));
  }
  return match;
}

absl::StatusOr<std::vector<int>> SheetDrawings(const SheetTimingTrack& track, int drawing_count,
                                               const std::string& what) {
  std::vector<int> drawings(track.cells.size(), -1);
  int first_drawing = -1;
  for (size_t row = 0; row < track.cells.size(); ++row) {
    const std::string& cell = track.cells[row];
    if (cell.empty()) {
      if (row > 0) drawings[row] = drawings[row - 1];  // blank: holds the drawing before
      continue;
    }
    int number = 0;
    const bool digits =
        cell.size() <= 9 && cell.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || !absl::SimpleAtoi(cell, &number) || number < 1 || number > drawing_count) {
      return absl::InvalidArgumentError(absl::StrCat(TrackLabel(track.name), ", frame ", row + 1,
                                                     ": cell ", QuoteForError(cell),
                                                     " names no drawing (cells are ", what, ")"));
    }
    drawings[row] = number - 1;
    if (first_drawing < 0) first_drawing = number - 1;
  }
  if (first_drawing < 0) {
    return absl::InvalidArgumentError(absl::StrCat(TrackLabel(track.name), ": every one of its ",
                                                   track.cells.size(),
                                                   " frames is blank (no drawing to show)"));
  }
  for (int& drawing : drawings) {
    if (drawing >= 0) break;
    drawing = first_drawing;  // blanks before the first drawing show it
  }
  return drawings;
}

}  // namespace koma::formats

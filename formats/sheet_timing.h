// A timing read back from a sheet an animator edited (`--timing-from`): an XDTS exposure sheet
// (as OpenToonz, CLIP STUDIO PAINT, TVPaint or koma wrote it) or koma's `--timing` CSV, as
// plain "sheet timing": per track, per sheet row, the cell shown. Then the rules that map it to
// koma's drawings: tracks matched by name, then by order; a cell id names a drawing (koma's
// skeletal sheets name each cell after the 1-based source frame it shows); a blank cell holds
// the drawing before it. docs/usage.md ("Timing from a sheet") has the rules for readers.
#ifndef KOMA_FORMATS_SHEET_TIMING_H_
#define KOMA_FORMATS_SHEET_TIMING_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "formats/xdts.h"

namespace koma::formats {

// One track (an XDTS Cell layer; the CSV's one column of source frames).
struct SheetTimingTrack {
  std::string name;  // the layer name ("" in a skeletal CSV; a drawing sheet's column name)
  std::vector<std::string> cells;  // per sheet row: the cell id, "" when blank
  // A drawing sheet CSV only, per row: its file line and its source_frame text ("" when
  // empty), checked against the drawing's tau by the caller (the drawing column is read).
  std::vector<int> lines;
  std::vector<std::string> stated_source_frames;
};

// What a sheet's cells name: XDTS cell ids; the source frames of koma's skeletal --timing
// CSV (cell = source_frame + 1); the drawings of `koma curves --timing`'s drawing sheet CSV
// (cell = drawing + 1, as the XDTS koma writes for the same answer).
enum class SheetKind { kXdts, kSourceFrameCsv, kDrawingCsv };

struct SheetTiming {
  SheetKind kind = SheetKind::kXdts;
  int rows = 0;  // sheet rows (an XDTS's duration; the CSV's grid frames or output frames)
  std::vector<SheetTimingTrack> tracks;
  // Rules applied that the reader should hear of ("2 extra time tables ignored: koma reads
  // the first").
  std::vector<std::string> warnings;
};

// The Cell tracks of the first time table of an XDTS file (ReadXdts: OpenToonz's import
// rules), a warning when there are more time tables. Errors are ReadXdts's.
absl::StatusOr<SheetTiming> ReadSheetTimingXdts(std::string_view text,
                                                const XdtsReadLimits& limits = {});

// koma's `--timing` CSV (formats/timing_sheet.h), edited in a spreadsheet: the header names
// the columns (any order; `source_frame` required, `grid_frame` optional, the others
// ignored: they go stale when rows are inserted), rows in file order. Without `grid_frame` a
// row is a sheet row; with it, the rows of one grid frame are one sheet row (they must show
// one source frame), grid frames must not decrease, and a grid frame no row names repeats
// the one before (as the XDTS rows do). A cell is source_frame + 1 (the XDTS cell id of that
// source frame), "" for an empty source_frame. A UTF-8 byte order mark, CRLF, spaces around
// values and blank lines are accepted. INVALID_ARGUMENT naming the line and value.
// A header with a `drawing` column is `koma curves --timing`'s drawing sheet instead
// (output_frame,drawing,source_frame,time_s[,G_drawing,G_source_frame...],keys): one track
// per `drawing` / `G_drawing` column (named so), a row per sheet row, cell = drawing + 1
// ("" when empty), the row's source_frame kept for the caller's check (kind kDrawingCsv).
absl::StatusOr<SheetTiming> ReadSheetTimingCsv(std::string_view text, int max_rows = 1 << 24);

// Which sheet track each of koma's tracks takes: a sheet track of the same name, else the
// first sheet track no name claimed, in order. A sheet track left over is INVALID_ARGUMENT
// naming it and koma's tracks ("track \"BG\": no such track: the clip's tracks are
// \"pitch\""); a koma track left without one too. Result: per koma track, its sheet track.
absl::StatusOr<std::vector<int>> MatchSheetTracks(const SheetTiming& sheet,
                                                  const std::vector<std::string>& koma_tracks);

// A track's cells as 0-based drawing indices: cell "n" (decimal digits, leading zeros
// allowed) is drawing n - 1 and must be 1 <= n <= drawing_count; a blank cell holds the
// drawing before it, blanks before the first drawing show the first drawing. Errors name the
// track, the frame (1-based, as the tools number rows) and the cell: `track "pitch", frame
// 12: cell "500" names no drawing (the drawings are 1 to 130)`; a track with no cell at all.
// `what` names the drawings in that message ("source frames 1 to 130").
absl::StatusOr<std::vector<int>> SheetDrawings(const SheetTimingTrack& track, int drawing_count,
                                               const std::string& what);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_SHEET_TIMING_H_

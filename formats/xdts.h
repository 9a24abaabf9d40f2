// XDTS (eXchange Digital Time Sheet, Celsys with Toei Animation, 2018): the exposure sheet
// CLIP STUDIO PAINT, OpenToonz, Tahoma2D and TVPaint read and write. A file is the literal
// first line "exchangeDigitalTimeSheet Save Data", then JSON: `version` 5 and `timeTables`,
// each with `duration` (rows), `name`, `timeTableHeaders` (layer names per field) and
// `fields` (per field, tracks of {frame, data[{id 0, values}]} entries). docs/formats.md has
// the mapping koma writes; field ids: 0 Cell, 3 Dialog, 5 Camerawork.
#ifndef KOMA_FORMATS_XDTS_H_
#define KOMA_FORMATS_XDTS_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"

namespace koma::formats {

inline constexpr char kXdtsIdentifier[] = "exchangeDigitalTimeSheet Save Data";
inline constexpr int kXdtsVersion = 5;
// Field ids of the published format.
inline constexpr int kXdtsCellField = 0;
inline constexpr int kXdtsDialogField = 3;
inline constexpr int kXdtsCameraworkField = 5;
// Special cell values.
inline constexpr char kXdtsNullCell[] = "SYMBOL_NULL_CELL";  // empty cell (x)
inline constexpr char kXdtsHyphen[] = "SYMBOL_HYPHEN";       // continue the previous
inline constexpr char kXdtsTick1[] = "SYMBOL_TICK_1";        // inbetween mark (o)
inline constexpr char kXdtsTick2[] = "SYMBOL_TICK_2";        // reverse sheet mark

// One layer of the Cell field: per sheet row (frame 0 .. duration - 1) the cell it shows, a
// drawing name such as "3" ("" = empty, SYMBOL_NULL_CELL).
struct XdtsCellTrack {
  std::string name;
  std::vector<std::string> cells;
};

// A line of dialogue on rows [begin, end).
struct XdtsDialogLine {
  int begin = 0;
  int end = 0;  // one past the last row
  std::string speaker;
  std::string text;
  friend bool operator==(const XdtsDialogLine& a, const XdtsDialogLine& b) {
    return a.begin == b.begin && a.end == b.end && a.speaker == b.speaker && a.text == b.text;
  }
};

// One layer of the Dialog field.
struct XdtsDialogTrack {
  std::string name;
  std::vector<XdtsDialogLine> lines;  // in time order, disjoint
};

// One time table (koma writes one).
struct XdtsSheet {
  std::string name;  // the time table's name
  int duration = 0;  // rows (frames of the sheet), >= 1
  std::vector<XdtsCellTrack> cell_tracks;      // trackNo 0, 1, ... (0 = the bottom layer)
  std::vector<XdtsDialogTrack> dialog_tracks;  // trackNo 0, 1, ...
  // ReadXdts: the time tables after the first, which it does not read (WriteXdts ignores it).
  int ignored_time_tables = 0;
};

// The file, as XDTS writers write it: a Cell track has an entry only where its cell changes
// (holds are implicit) and ends with SYMBOL_NULL_CELL at frame `duration`, the row after the
// sheet (OpenToonz's exporter closes a column so); a dialog line is [speaker, text] on its first
// row and SYMBOL_HYPHEN on each further row. One frame entry per line; names and texts as JSON
// strings (UTF-8 kept, quotes and control characters escaped; invalid UTF-8 becomes U+FFFD).
// Requires duration >= 1, every track `duration` cells, lines within [0, duration).
// Deterministic: the same sheet gives the same bytes.
std::string WriteXdts(const XdtsSheet& sheet);

// Limits of ReadXdts.
struct XdtsReadLimits {
  int max_rows = 1 << 24;  // duration and frame numbers (a sheet of 16.7 M rows: 194 hours)
  int max_tracks = 4096;   // tracks per field
};

// Reads the first time table of an XDTS file the way OpenToonz imports one: the identifier on
// the first line (a UTF-8 byte order mark and CR before the line end are accepted), version 5;
// a Cell track's entries in frame order, the rows between entries repeating the cell before
// (rows before the first entry empty), SYMBOL_HYPHEN and the tick symbols repeating the
// previous cell, SYMBOL_NULL_CELL empty, and the last cell, unless empty, continued to the
// sheet's end; entries at or past `duration` only end the track. Layer names come from the
// field's header by trackNo (empty when it has none). Dialog: a line from an entry whose first
// value is not SYMBOL_HYPHEN through the last SYMBOL_HYPHEN entry after it. Camerawork and
// other fields are skipped. INVALID_ARGUMENT naming the line or JSON path and value
// ("timeTables[0].fields[0].tracks[1].frames[4].frame: -2 must be >= 0").
absl::StatusOr<XdtsSheet> ReadXdts(std::string_view text, const XdtsReadLimits& limits = {});

}  // namespace koma::formats

#endif  // KOMA_FORMATS_XDTS_H_

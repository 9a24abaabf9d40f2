// ReadXdts: OpenToonz's import rules (toonz/sources/toonz/xdtsio.cpp) on a checked document,
// every malformed part named by its JSON path.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/error_text.h"
#include "formats/json_text.h"
#include "formats/xdts.h"
#include "nlohmann/json.hpp"

namespace koma::formats {
namespace {

using Json = nlohmann::ordered_json;  // as ParseJsonTextWithin reads it

// Deeper nesting than any XDTS document has (7 levels) is refused before parsing, so a
// hostile file cannot recurse the parser deep.
constexpr int kMaxDepth = 64;

absl::Status PathError(const std::string& path, const std::string& what) {
  if (path.empty()) return absl::InvalidArgumentError(what);  // the document itself
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", what));
}

// The value as JSON text (a string keeps its quotes), cut to kMaxQuotedBytes.
std::string Describe(const Json& value) {
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > kMaxQuotedBytes) text = text.substr(0, kMaxQuotedBytes) + "...";
  return text;
}

absl::StatusOr<const Json*> Member(const Json& object, const std::string& path,
                                   const char* name) {
  if (!object.is_object()) return PathError(path, "expected an object, got " + Describe(object));
  const auto it = object.find(name);
  if (it == object.end()) return PathError(path, absl::StrCat("missing \"", name, "\""));
  return &*it;
}

absl::StatusOr<const Json*> ArrayMember(const Json& object, const std::string& path,
                                        const char* name) {
  KOMA_ASSIGN_OR_RETURN(const Json* value, Member(object, path, name));
  if (!value->is_array()) {
    return PathError(absl::StrCat(path, path.empty() ? "" : ".", name),
                     "expected an array, got " + Describe(*value));
  }
  return value;
}

// An integer in [lo, hi] (a JSON number with no fraction: 3 or 3.0).
absl::StatusOr<int> IntAt(const Json& value, const std::string& path, int lo, int hi) {
  double number = 0;
  if (value.is_number_integer() || value.is_number_unsigned()) {
    number = value.get<double>();
  } else if (value.is_number_float()) {
    number = value.get<double>();
    if (number != static_cast<double>(static_cast<long long>(number))) {
      return PathError(path, "expected a whole number, got " + Describe(value));
    }
  } else {
    return PathError(path, "expected a whole number, got " + Describe(value));
  }
  if (number < lo) return PathError(path, absl::StrCat(Describe(value), " must be >= ", lo));
  if (number > hi) return PathError(path, absl::StrCat(Describe(value), " must be <= ", hi));
  return static_cast<int>(number);
}

absl::StatusOr<std::string> StringAt(const Json& value, const std::string& path) {
  if (!value.is_string()) return PathError(path, "expected a string, got " + Describe(value));
  return value.get<std::string>();
}

// One track entry: its frame and its first instruction's values.
struct Entry {
  int frame = 0;
  std::vector<std::string> values;
};

absl::StatusOr<std::vector<Entry>> ReadEntries(const Json& track, const std::string& path,
                                               const XdtsReadLimits& limits) {
  KOMA_ASSIGN_OR_RETURN(const Json* frames, ArrayMember(track, path, "frames"));
  std::vector<Entry> entries;
  for (size_t i = 0; i < frames->size(); ++i) {
    const std::string at = absl::StrCat(path, ".frames[", i, "]");
    const Json& item = (*frames)[i];
    Entry entry;
    KOMA_ASSIGN_OR_RETURN(const Json* frame, Member(item, at, "frame"));
    KOMA_ASSIGN_OR_RETURN(entry.frame, IntAt(*frame, at + ".frame", 0, limits.max_rows));
    KOMA_ASSIGN_OR_RETURN(const Json* data, ArrayMember(item, at, "data"));
    if (data->empty()) return PathError(at + ".data", "expected at least one instruction");
    const std::string data_at = at + ".data[0]";
    KOMA_ASSIGN_OR_RETURN(const Json* values, ArrayMember((*data)[0], data_at, "values"));
    if (values->empty()) return PathError(data_at + ".values", "expected at least one value");
    for (size_t v = 0; v < values->size(); ++v) {
      KOMA_ASSIGN_OR_RETURN(std::string value,
                            StringAt((*values)[v], absl::StrCat(data_at, ".values[", v, "]")));
      entry.values.push_back(std::move(value));
    }
    entries.push_back(std::move(entry));
  }
  // OpenToonz sorts by frame; a stable sort keeps a file's order among equal frames.
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.frame < b.frame; });
  return entries;
}

bool RepeatsPrevious(const std::string& value) {
  return value == kXdtsHyphen || value == kXdtsTick1 || value == kXdtsTick2;
}

// OpenToonz's XdtsFieldTrackItem::getCellFrameIdTrack and the column fill of loadXdtsScene.
std::vector<std::string> ExpandCells(const std::vector<Entry>& entries, int duration) {
  std::vector<std::string> cells;
  cells.reserve(static_cast<size_t>(duration));
  for (const Entry& entry : entries) {
    if (entry.frame >= duration) break;  // past the sheet: only closes the track
    const std::string previous = cells.empty() ? std::string() : cells.back();
    while (static_cast<int>(cells.size()) < entry.frame) cells.push_back(previous);
    const std::string& value = entry.values[0];
    std::string cell = value == kXdtsNullCell ? std::string()
                       : RepeatsPrevious(value) ? (cells.empty() ? std::string() : cells.back())
                                                : value;
    if (static_cast<int>(cells.size()) == entry.frame) {
      cells.push_back(std::move(cell));
    } else {
      cells.back() = std::move(cell);  // a second entry on one frame: the later wins
    }
  }
  // The last cell, unless empty, runs to the end of the sheet.
  const std::string last = cells.empty() ? std::string() : cells.back();
  while (static_cast<int>(cells.size()) < duration) cells.push_back(last);
  return cells;
}

absl::StatusOr<std::vector<XdtsDialogLine>> DialogLines(const std::vector<Entry>& entries,
                                                        int duration, const std::string& path) {
  std::vector<XdtsDialogLine> lines;
  for (const Entry& entry : entries) {
    if (entry.frame >= duration) break;
    if (entry.values[0] == kXdtsHyphen) {
      if (lines.empty()) {
        return PathError(path, absl::StrCat("SYMBOL_HYPHEN at frame ", entry.frame,
                                            " continues no line"));
      }
      lines.back().end = entry.frame + 1;
      continue;
    }
    XdtsDialogLine line;
    line.begin = entry.frame;
    line.end = entry.frame + 1;
    line.speaker = entry.values[0];
    if (entry.values.size() > 1) line.text = entry.values[1];
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace

absl::StatusOr<XdtsSheet> ReadXdts(std::string_view text, const XdtsReadLimits& limits) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const size_t line_end = text.find('\n');
  std::string_view first = text.substr(0, line_end);
  if (!first.empty() && first.back() == '\r') first.remove_suffix(1);
  if (first != kXdtsIdentifier) {
    return absl::InvalidArgumentError(
        absl::StrCat("line 1: expected \"", kXdtsIdentifier, "\" (an XDTS file), got ",
                     QuoteForError(first)));
  }
  const std::string_view body =
      line_end == std::string_view::npos ? std::string_view() : text.substr(line_end + 1);
  // Nesting deeper than kMaxDepth or invalid JSON: "line 2 on: invalid JSON at byte 12: ...".
  absl::StatusOr<Json> parsed = ParseJsonTextWithin(body, kMaxDepth);
  if (!parsed.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("line 2 on: ", parsed.status().message()));
  }
  const Json document = *std::move(parsed);
  KOMA_ASSIGN_OR_RETURN(const Json* version, Member(document, "", "version"));
  if (!version->is_number() || version->get<double>() != kXdtsVersion) {
    return PathError("version", absl::StrCat(Describe(*version), " is not ", kXdtsVersion,
                                             " (the XDTS version koma reads)"));
  }
  KOMA_ASSIGN_OR_RETURN(const Json* tables, ArrayMember(document, "", "timeTables"));
  if (tables->empty()) return PathError("timeTables", "expected at least one time table");
  const Json& table = (*tables)[0];
  const std::string at = "timeTables[0]";
  XdtsSheet sheet;
  sheet.ignored_time_tables = static_cast<int>(tables->size()) - 1;
  KOMA_ASSIGN_OR_RETURN(const Json* duration, Member(table, at, "duration"));
  KOMA_ASSIGN_OR_RETURN(sheet.duration, IntAt(*duration, at + ".duration", 1, limits.max_rows));
  if (const auto name = table.find("name"); name != table.end()) {
    KOMA_ASSIGN_OR_RETURN(sheet.name, StringAt(*name, at + ".name"));
  }
  // Layer names per field id.
  std::vector<std::string> cell_names, dialog_names;
  KOMA_ASSIGN_OR_RETURN(const Json* headers, ArrayMember(table, at, "timeTableHeaders"));
  for (size_t h = 0; h < headers->size(); ++h) {
    const std::string header_at = absl::StrCat(at, ".timeTableHeaders[", h, "]");
    KOMA_ASSIGN_OR_RETURN(const Json* field_id, Member((*headers)[h], header_at, "fieldId"));
    KOMA_ASSIGN_OR_RETURN(const int id, IntAt(*field_id, header_at + ".fieldId", 0, 1 << 20));
    KOMA_ASSIGN_OR_RETURN(const Json* names, ArrayMember((*headers)[h], header_at, "names"));
    if (id != kXdtsCellField && id != kXdtsDialogField) continue;
    std::vector<std::string>& out = id == kXdtsCellField ? cell_names : dialog_names;
    out.clear();
    for (size_t n = 0; n < names->size(); ++n) {
      KOMA_ASSIGN_OR_RETURN(std::string name,
                            StringAt((*names)[n], absl::StrCat(header_at, ".names[", n, "]")));
      out.push_back(std::move(name));
    }
  }
  const auto fields = table.find("fields");
  if (fields != table.end() && !fields->is_array()) {
    return PathError(at + ".fields", "expected an array, got " + Describe(*fields));
  }
  const size_t field_count = fields == table.end() ? 0 : fields->size();
  for (size_t f = 0; f < field_count; ++f) {
    const std::string field_at = absl::StrCat(at, ".fields[", f, "]");
    const Json& field = (*fields)[f];
    KOMA_ASSIGN_OR_RETURN(const Json* field_id, Member(field, field_at, "fieldId"));
    KOMA_ASSIGN_OR_RETURN(const int id, IntAt(*field_id, field_at + ".fieldId", 0, 1 << 20));
    if (id != kXdtsCellField && id != kXdtsDialogField) continue;
    KOMA_ASSIGN_OR_RETURN(const Json* tracks, ArrayMember(field, field_at, "tracks"));
    if (tracks->size() > static_cast<size_t>(limits.max_tracks)) {
      return PathError(field_at + ".tracks", absl::StrCat(tracks->size(), " tracks is over the "
                                                          "limit of ", limits.max_tracks));
    }
    const std::vector<std::string>& names = id == kXdtsCellField ? cell_names : dialog_names;
    for (size_t t = 0; t < tracks->size(); ++t) {
      const std::string track_at = absl::StrCat(field_at, ".tracks[", t, "]");
      KOMA_ASSIGN_OR_RETURN(const Json* track_no, Member((*tracks)[t], track_at, "trackNo"));
      KOMA_ASSIGN_OR_RETURN(const int no,
                            IntAt(*track_no, track_at + ".trackNo", 0, limits.max_tracks - 1));
      KOMA_ASSIGN_OR_RETURN(const std::vector<Entry> entries,
                            ReadEntries((*tracks)[t], track_at, limits));
      const std::string name = static_cast<size_t>(no) < names.size() ? names[no] : "";
      if (id == kXdtsCellField) {
        sheet.cell_tracks.push_back({name, ExpandCells(entries, sheet.duration)});
      } else {
        KOMA_ASSIGN_OR_RETURN(std::vector<XdtsDialogLine> lines,
                              DialogLines(entries, sheet.duration, track_at));
        sheet.dialog_tracks.push_back({name, std::move(lines)});
      }
    }
  }
  return sheet;
}

}  // namespace koma::formats

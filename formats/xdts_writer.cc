// WriteXdts: the layout is fixed by hand (one frame entry per line) so a long sheet stays a
// readable, diffable file; strings go through nlohmann's escaping.
#include <cassert>
#include <string>

#include "absl/strings/str_cat.h"
#include "formats/xdts.h"
#include "nlohmann/json.hpp"

namespace koma::formats {
namespace {

// `text` as a JSON string: UTF-8 kept as is, quotes, backslashes and control characters
// escaped, bytes that are not UTF-8 replaced by U+FFFD (JSON text is UTF-8).
std::string JsonString(const std::string& text) {
  return nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// One entry: {"data": [{"id": 0, "values": [...]}], "frame": F}.
void AppendEntry(std::string* out, int frame, const std::vector<std::string>& values, bool last) {
  absl::StrAppend(out, "                {\"data\": [{\"id\": 0, \"values\": [");
  for (size_t i = 0; i < values.size(); ++i) {
    absl::StrAppend(out, i > 0 ? ", " : "", JsonString(values[i]));
  }
  absl::StrAppend(out, "]}], \"frame\": ", frame, last ? "}\n" : "},\n");
}

void AppendTrackStart(std::string* out) { out->append("            {\n              \"frames\": [\n"); }

void AppendTrackEnd(std::string* out, int track_no, bool last) {
  absl::StrAppend(out, "              ],\n              \"trackNo\": ", track_no,
                  last ? "\n            }\n" : "\n            },\n");
}

// A Cell track: an entry where the cell changes, SYMBOL_NULL_CELL for an empty cell, and the
// closing SYMBOL_NULL_CELL at frame `duration`.
void AppendCellTrack(std::string* out, const XdtsCellTrack& track, int track_no, int duration,
                     bool last) {
  assert(static_cast<int>(track.cells.size()) == duration);
  AppendTrackStart(out);
  const std::string null_cell(kXdtsNullCell);
  for (int row = 0; row < duration; ++row) {
    const std::string& cell = track.cells[static_cast<size_t>(row)];
    if (row > 0 && cell == track.cells[static_cast<size_t>(row) - 1]) continue;
    AppendEntry(out, row, {cell.empty() ? null_cell : cell}, false);
  }
  AppendEntry(out, duration, {null_cell}, true);
  AppendTrackEnd(out, track_no, last);
}

// A Dialog track: [speaker, text] on a line's first row, SYMBOL_HYPHEN on each further row.
void AppendDialogTrack(std::string* out, const XdtsDialogTrack& track, int track_no, bool last) {
  AppendTrackStart(out);
  const std::string hyphen(kXdtsHyphen);
  for (size_t l = 0; l < track.lines.size(); ++l) {
    const XdtsDialogLine& line = track.lines[l];
    assert(line.begin < line.end);
    for (int row = line.begin; row < line.end; ++row) {
      const bool final_entry = l + 1 == track.lines.size() && row + 1 == line.end;
      if (row == line.begin) {
        AppendEntry(out, row, {line.speaker, line.text}, final_entry);
      } else {
        AppendEntry(out, row, {hyphen}, final_entry);
      }
    }
  }
  AppendTrackEnd(out, track_no, last);
}

void AppendNames(std::string* out, int field_id, const std::vector<std::string>& names,
                 bool last) {
  absl::StrAppend(out, "        {\"fieldId\": ", field_id, ", \"names\": [");
  for (size_t i = 0; i < names.size(); ++i) {
    absl::StrAppend(out, i > 0 ? ", " : "", JsonString(names[i]));
  }
  out->append(last ? "]}\n" : "]},\n");
}

}  // namespace

std::string WriteXdts(const XdtsSheet& sheet) {
  assert(sheet.duration >= 1);
  // Dialog tracks with no line get a header name but no track (trackNo keeps their index).
  bool any_dialog = false;
  for (const XdtsDialogTrack& track : sheet.dialog_tracks) any_dialog |= !track.lines.empty();

  std::string out;
  absl::StrAppend(&out, kXdtsIdentifier, "\n{\n  \"timeTables\": [\n    {\n");
  absl::StrAppend(&out, "      \"duration\": ", sheet.duration, ",\n      \"fields\": [\n");
  absl::StrAppend(&out, "        {\n          \"fieldId\": ", kXdtsCellField,
                  ",\n          \"tracks\": [\n");
  for (size_t t = 0; t < sheet.cell_tracks.size(); ++t) {
    AppendCellTrack(&out, sheet.cell_tracks[t], static_cast<int>(t), sheet.duration,
                    t + 1 == sheet.cell_tracks.size());
  }
  absl::StrAppend(&out, "          ]\n        }", any_dialog ? ",\n" : "\n");
  if (any_dialog) {
    absl::StrAppend(&out, "        {\n          \"fieldId\": ", kXdtsDialogField,
                    ",\n          \"tracks\": [\n");
    size_t last_with_lines = 0;
    for (size_t t = 0; t < sheet.dialog_tracks.size(); ++t) {
      if (!sheet.dialog_tracks[t].lines.empty()) last_with_lines = t;
    }
    for (size_t t = 0; t < sheet.dialog_tracks.size(); ++t) {
      if (sheet.dialog_tracks[t].lines.empty()) continue;
      AppendDialogTrack(&out, sheet.dialog_tracks[t], static_cast<int>(t), t == last_with_lines);
    }
    out.append("          ]\n        }\n");
  }
  absl::StrAppend(&out, "      ],\n      \"name\": ", JsonString(sheet.name),
                  ",\n      \"timeTableHeaders\": [\n");
  std::vector<std::string> names;
  for (const XdtsCellTrack& track : sheet.cell_tracks) names.push_back(track.name);
  AppendNames(&out, kXdtsCellField, names, !any_dialog);
  if (any_dialog) {
    names.clear();
    for (const XdtsDialogTrack& track : sheet.dialog_tracks) names.push_back(track.name);
    AppendNames(&out, kXdtsDialogField, names, true);
  }
  absl::StrAppend(&out, "      ]\n    }\n  ],\n  \"version\": ", kXdtsVersion, "\n}\n");
  return out;
}

}  // namespace koma::formats

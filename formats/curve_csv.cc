#include "formats/curve_csv.h"

#include <cassert>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstddef>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "formats/error_text.h"
#include "formats/number_format.h"

namespace koma::formats {
namespace {

constexpr std::string_view kFrameHeader = "frame";

// The lines of `text` without their "\n" or "\r\n"; a final line break does not start another
// line. "" -> no lines.
std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return lines;
}

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  while (true) {
    const size_t comma = line.find(',');
    fields.push_back(line.substr(0, comma));
    if (comma == std::string_view::npos) return fields;
    line.remove_prefix(comma + 1);
  }
}

absl::Status LineError(size_t line, const std::string& message) {
  return absl::InvalidArgumentError(absl::StrCat("line ", line, ": ", message));
}

// "line L, column C: message", or with an id "line L, column C (\"id\"): message".
absl::Status FieldError(size_t line, size_t column, const std::string& message,
                        std::string_view id = {}) {
  const std::string where = absl::StrCat("line ", line, ", column ", column);
  return absl::InvalidArgumentError(
      id.empty() ? absl::StrCat(where, ": ", message)
                 : absl::StrCat(where, " (", QuoteForError(id), "): ", message));
}

bool HasQuoteOrControl(std::string_view id) {
  for (const char c : id) {
    if (c == '"' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  }
  return false;
}

absl::StatusOr<std::vector<std::string>> ParseHeader(std::string_view line) {
  const std::vector<std::string_view> fields = SplitFields(line);
  if (fields[0] != kFrameHeader) {
    return FieldError(1, 1, absl::StrCat("expected \"frame\", got ", QuoteForError(fields[0])));
  }
  if (fields.size() < 2) return LineError(1, "expected at least one curve id after \"frame\"");
  std::vector<std::string> ids;
  std::unordered_map<std::string_view, size_t> column_of_id;
  for (size_t column = 2; column <= fields.size(); ++column) {
    const std::string_view id = fields[column - 1];
    if (id.empty()) return FieldError(1, column, "empty curve id");
    if (HasQuoteOrControl(id)) {
      return FieldError(
          1, column,
          absl::StrCat("curve id ", QuoteForError(id), " contains a quote or a control character"));
    }
    const auto [it, inserted] = column_of_id.emplace(id, column);
    if (!inserted) {
      return FieldError(1, column,
                        absl::StrCat("duplicate curve id ", QuoteForError(id), " (also column ",
                                     it->second, ")"));
    }
    ids.emplace_back(id);
  }
  return ids;
}

// Row `row` (frame `row`, on line `line`) into the samples of `set`'s curves.
absl::Status ParseRow(std::string_view text, size_t line, int row, CurveSet& set) {
  const std::vector<std::string_view> fields = SplitFields(text);
  const size_t expected = set.curves.size() + 1;
  if (fields.size() != expected) {
    return LineError(
        line,
        absl::StrCat("expected ", expected, " fields (frame and ", set.curves.size(),
                     set.curves.size() == 1 ? " curve" : " curves", "), got ", fields.size()));
  }
  const std::string_view frame = fields[0];
  int value = -1;
  const char* end = frame.data() + frame.size();
  const auto [ptr, ec] = std::from_chars(frame.data(), end, value);
  const bool digits_only = !frame.empty() && frame.front() != '-' && frame.front() != '+';
  if (ec != std::errc() || ptr != end || !digits_only || value != row) {
    return FieldError(line, 1,
                      absl::StrCat("expected frame ", row, ", got ", QuoteForError(frame)));
  }
  for (size_t c = 0; c < set.curves.size(); ++c) {
    absl::StatusOr<double> number = ParseDouble(fields[c + 1]);
    if (!number.ok()) {
      return FieldError(line, c + 2, std::string(number.status().message()), set.curves[c].id);
    }
    set.curves[c].samples.push_back(*number);
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<CurveSet> ParseCurveCsv(std::string_view text, double fps) {
  if (!std::isfinite(fps) || !(fps > 0.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("fps: expected a number > 0, got ", FormatDouble(fps)));
  }
  const std::vector<std::string_view> lines = SplitLines(text);
  if (lines.empty()) return LineError(1, "missing header \"frame,<id>,...\"");
  if (lines[0].empty()) return LineError(1, "empty line (expected the header)");
  KOMA_ASSIGN_OR_RETURN(const std::vector<std::string> ids, ParseHeader(lines[0]));
  if (lines.size() < 2) return LineError(2, "expected a row for frame 0 after the header");
  if (lines.size() - 1 > static_cast<size_t>(INT_MAX)) {
    return absl::OutOfRangeError(absl::StrCat(lines.size() - 1, " rows"));
  }
  CurveSet set;
  set.fps = fps;
  set.frame_count = static_cast<int>(lines.size() - 1);
  for (const std::string& id : ids) {
    Curve curve;
    curve.id = id;
    curve.samples.reserve(static_cast<size_t>(set.frame_count));
    set.curves.push_back(std::move(curve));
  }
  for (int row = 0; row < set.frame_count; ++row) {
    const size_t line = static_cast<size_t>(row) + 2;  // 1-based, after the header
    if (lines[line - 1].empty()) return LineError(line, "empty line");
    KOMA_RETURN_IF_ERROR(ParseRow(lines[line - 1], line, row, set));
  }
  return set;
}

std::string WriteCurveCsv(const std::vector<std::string>& ids,
                          const std::vector<std::vector<double>>& values_per_curve) {
  assert(ids.size() == values_per_curve.size());
  std::string out(kFrameHeader);
  for (const std::string& id : ids) absl::StrAppend(&out, ",", id);
  out += '\n';
  const size_t frames = values_per_curve.empty() ? 0 : values_per_curve[0].size();
  for (size_t frame = 0; frame < frames; ++frame) {
    absl::StrAppend(&out, frame);
    for (const std::vector<double>& values : values_per_curve) {
      assert(values.size() == frames);
      absl::StrAppend(&out, ",", FormatDouble(values[frame]));
    }
    out += '\n';
  }
  return out;
}

}  // namespace koma::formats

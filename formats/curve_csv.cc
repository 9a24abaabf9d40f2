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
#include "formats/text_encoding.h"

namespace koma::formats {
namespace {

constexpr std::string_view kFrameHeader = "frame";

// One CSV record: its fields (unquoted) and the line it starts on (1-based).
struct Record {
  size_t line = 0;
  std::vector<std::string> fields;
  bool blank = false;  // an empty line: one empty, unquoted field
};

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

// RFC 4180 records of `text` split at `separator`: a field is plain text without quotes, or
// a quoted field "..." in which "" is a quote and separators and line breaks are text. A
// record ends at LF or CRLF outside quotes; a final line break does not start another record.
absl::StatusOr<std::vector<Record>> SplitRecords(std::string_view text, char separator) {
  std::vector<Record> records;
  size_t line = 1;
  size_t i = 0;
  while (i < text.size()) {
    Record record;
    record.line = line;
    size_t column = 1;
    while (true) {  // one field per pass
      std::string field;
      if (i < text.size() && text[i] == '"') {
        const size_t opened_line = line;
        ++i;
        while (true) {
          if (i >= text.size()) {
            return FieldError(opened_line, column,
                              "a quoted field is not closed (a \" is missing)");
          }
          const char c = text[i++];
          if (c == '"') {
            if (i < text.size() && text[i] == '"') {
              field += '"';
              ++i;
              continue;
            }
            break;
          }
          if (c == '\n') ++line;
          field += c;
        }
        const bool at_end = i >= text.size() || text[i] == separator || text[i] == '\n' ||
                            (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n');
        if (!at_end) {
          return FieldError(line, column,
                            "text after the closing quote of a quoted field (write a quote inside "
                            "as \"\")");
        }
      } else {
        const size_t begin = i;
        while (i < text.size() && text[i] != separator && text[i] != '\n') ++i;
        std::string_view plain = text.substr(begin, i - begin);
        if (i < text.size() && text[i] == '\n' && !plain.empty() && plain.back() == '\r') {
          plain.remove_suffix(1);
        }
        if (plain.find('"') != std::string_view::npos) {
          return FieldError(line, column,
                            "a quote inside an unquoted field (quote the whole field and double "
                            "the quote: \"a\"\"b\")");
        }
        field = std::string(plain);
        if (record.fields.empty() && field.empty() && (i >= text.size() || text[i] == '\n')) {
          record.blank = true;
        }
      }
      record.fields.push_back(std::move(field));
      if (i < text.size() && text[i] == separator) {
        ++i;
        ++column;
        continue;
      }
      if (i < text.size() && text[i] == '\r') ++i;  // the CR of a CRLF after a quoted field
      if (i < text.size() && text[i] == '\n') {
        ++i;
        ++line;
      }
      break;
    }
    records.push_back(std::move(record));
  }
  return records;
}

// The header's separator: ';' when the first field ("frame", quoted or not) is followed by
// one (spreadsheets in locales whose decimal mark is a comma), else ','.
char DetectSeparator(std::string_view text) {
  for (std::string_view header : {"frame;", "\"frame\";"}) {
    if (text.substr(0, header.size()) == header) return ';';
  }
  return ',';
}

absl::StatusOr<std::vector<std::string>> ParseHeader(const Record& header) {
  const std::vector<std::string>& fields = header.fields;
  if (fields[0] != kFrameHeader) {
    return FieldError(header.line, 1,
                      absl::StrCat("expected \"frame\", got ", QuoteForError(fields[0])));
  }
  if (fields.size() < 2) {
    return LineError(header.line, "expected at least one curve id after \"frame\"");
  }
  std::vector<std::string> ids;
  std::unordered_map<std::string_view, size_t> column_of_id;
  for (size_t column = 2; column <= fields.size(); ++column) {
    const std::string& id = fields[column - 1];
    if (id.empty()) return FieldError(header.line, column, "empty curve id");
    const auto [it, inserted] = column_of_id.emplace(id, column);
    if (!inserted) {
      return FieldError(header.line, column,
                        absl::StrCat("duplicate curve id ", QuoteForError(id), " (also column ",
                                     it->second, ")"));
    }
    ids.emplace_back(id);
  }
  return ids;
}

// Row `row` (frame `row`) into the samples of `set`'s curves. With `decimal_comma` (a ';'
// file), a value's ',' is its decimal mark.
absl::Status ParseRow(const Record& record, int row, bool decimal_comma, CurveSet& set) {
  const std::vector<std::string>& fields = record.fields;
  const size_t line = record.line;
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
    std::string text = fields[c + 1];
    if (decimal_comma && text.find('.') == std::string::npos) {
      const size_t comma = text.find(',');
      if (comma != std::string::npos && text.find(',', comma + 1) == std::string::npos) {
        text[comma] = '.';
      }
    }
    absl::StatusOr<double> number = ParseDouble(text);
    if (!number.ok()) {
      return FieldError(line, c + 2, std::string(number.status().message()), set.curves[c].id);
    }
    set.curves[c].samples.push_back(*number);
  }
  return absl::OkStatus();
}

// The field as written: quoted (quotes doubled) when it holds a separator (',' or ';'), a
// quote or a line break, or starts or ends with white space that a reader might trim.
std::string QuoteField(const std::string& field) {
  const bool needs_quotes = field.find_first_of(",;\"\r\n") != std::string::npos ||
                            (!field.empty() && (field.front() == ' ' || field.front() == '\t' ||
                                                field.back() == ' ' || field.back() == '\t'));
  if (!needs_quotes) return field;
  std::string out = "\"";
  for (const char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

}  // namespace

absl::StatusOr<CurveSet> ParseCurveCsv(std::string_view text, double fps) {
  if (!std::isfinite(fps) || !(fps > 0.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("fps: expected a number > 0, got ", FormatDouble(fps)));
  }
  // A UTF-8 byte order mark is skipped (Excel's "CSV UTF-8"); UTF-16 is refused.
  KOMA_ASSIGN_OR_RETURN(text, SkipUtf8Bom(text));
  const char separator = DetectSeparator(text);
  KOMA_ASSIGN_OR_RETURN(const std::vector<Record> records, SplitRecords(text, separator));
  if (records.empty()) return LineError(1, "missing header \"frame,<id>,...\"");
  if (records[0].blank) return LineError(1, "empty line (expected the header)");
  KOMA_ASSIGN_OR_RETURN(const std::vector<std::string> ids, ParseHeader(records[0]));
  if (records.size() < 2) {
    return LineError(records[0].line + 1, "expected a row for frame 0 after the header");
  }
  if (records.size() - 1 > static_cast<size_t>(INT_MAX)) {
    return absl::OutOfRangeError(absl::StrCat(records.size() - 1, " rows"));
  }
  CurveSet set;
  set.fps = fps;
  set.frame_count = static_cast<int>(records.size() - 1);
  for (const std::string& id : ids) {
    Curve curve;
    curve.id = id;
    curve.samples.reserve(static_cast<size_t>(set.frame_count));
    set.curves.push_back(std::move(curve));
  }
  for (int row = 0; row < set.frame_count; ++row) {
    const Record& record = records[static_cast<size_t>(row) + 1];
    if (record.blank) return LineError(record.line, "empty line");
    KOMA_RETURN_IF_ERROR(ParseRow(record, row, separator == ';', set));
  }
  return set;
}

std::string WriteCurveCsv(const std::vector<std::string>& ids,
                          const std::vector<std::vector<double>>& values_per_curve) {
  assert(ids.size() == values_per_curve.size());
  std::string out(kFrameHeader);
  for (const std::string& id : ids) absl::StrAppend(&out, ",", QuoteField(id));
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

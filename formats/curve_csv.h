// Per-frame curves as CSV, for tools without Live2D support (spreadsheets, DCC scripts):
//
//   frame,ParamAngleX,ParamAngleY
//   0,0,0
//   1,0.5,-0.25
//   ...
//
// The header is "frame" followed by the curve ids; then one row per frame 0 .. N-1 with the
// frame index and each curve's value at that frame. Fields follow RFC 4180: a field may be
// quoted ("Param,X"), with a quote inside written twice ("say ""hi"""), and a quoted field may
// hold separators and line breaks, so any curve id round-trips. Spreadsheet exports are read
// too: a UTF-8 byte order mark is skipped, and a header "frame;..." makes ';' the separator
// (Excel in locales whose decimal mark is a comma), in which case a value's one ',' is its
// decimal mark ("0,5" is 0.5).
#ifndef KOMA_FORMATS_CURVE_CSV_H_
#define KOMA_FORMATS_CURVE_CSV_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/curves.h"

namespace koma::formats {

// Reads the CSV into dense curves (Curve::samples, one per row) at `fps` frames per second:
// frame_count = number of rows, curves in column order. LF or CRLF line endings; the last
// line may or may not end with one.
//
// INVALID_ARGUMENT naming "line L" and, for a field, "column C" (fields counted from 1) and
// the curve id, e.g. `line 4, column 3 ("ParamAngleY"): invalid number "x": ...`, for: fps not
// finite and > 0, an empty text, a first header field other than "frame", no curve column,
// an empty or duplicate id, a quote inside an unquoted field, text after a closing quote, a
// quoted field never closed, an empty line, a row with more or fewer
// fields than the header, a frame field other than the row's index written as decimal digits
// (a missing, repeated or out-of-order frame), a value ParseDouble rejects (including nan,
// inf and surrounding spaces), and no rows after the header. Curve semantics such as
// frame_count >= 2 are ValidateCurveSet's job.
absl::StatusOr<CurveSet> ParseCurveCsv(std::string_view text, double fps);

// The CSV for `ids` (header order) and their values (values_per_curve[c][frame]): "frame" and
// the ids, then one row per frame with every number written by FormatDouble, ',' separators,
// LF line endings including after the last row. With no curves, just "frame\n". An id is
// quoted when it holds ',', ';', a quote or a line break, or starts or ends with a space or
// tab. Requires ids.size() == values_per_curve.size(), equally long value vectors, finite
// values and non-empty, distinct ids (checked with assert only); then
// ParseCurveCsv(WriteCurveCsv(ids, values), fps) gives back the same ids and values, bit for
// bit (-0 reads back as +0).
std::string WriteCurveCsv(const std::vector<std::string>& ids,
                          const std::vector<std::vector<double>>& values_per_curve);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_CURVE_CSV_H_

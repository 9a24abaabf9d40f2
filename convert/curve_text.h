// Curve files as text, for `koma curves|lipblink` and for the server's file-carrying requests:
// motion3.json or per-frame CSV in, the same format out with some curves replaced. One
// implementation on both sides, so a file retimed by the server is byte for byte the file the
// CLI writes.
#ifndef KOMA_CONVERT_CURVE_TEXT_H_
#define KOMA_CONVERT_CURVE_TEXT_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/curves.h"
#include "formats/motion3.h"

namespace koma::convert {

struct CurveInput {
  std::optional<formats::Motion3File> motion3;  // kept to write every other field back
  CurveSet curves;
};

// A motion3.json text, or (`csv`) a CSV text (`frame,<id>,...`) at `csv_fps` frames per
// second. Errors are the readers' own (formats/motion3.h, formats/curve_csv.h), without a
// file name: the caller prefixes the path or the request field.
absl::StatusOr<CurveInput> ParseCurveText(std::string_view text, bool csv, double csv_fps);

// A retimed curve: per-frame values and the same as stepped keyframes.
struct CurveReplacement {
  std::vector<double> values;
  std::vector<CurvePoint> steps;
};

// `input` with replacements[i] (when set) in place of curve i: as CSV (every curve, the others
// sampled at every frame) when `csv`, else as motion3.json (needs a motion3 input; the others
// untouched, Meta counts recomputed). INVALID_ARGUMENT for motion3 output of a CSV input.
absl::StatusOr<std::string> CurveOutputText(
    const CurveInput& input, const std::vector<std::optional<CurveReplacement>>& replacements,
    bool csv);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_CURVE_TEXT_H_

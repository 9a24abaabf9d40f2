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
#include "formats/spine.h"

namespace koma::convert {

struct CurveInput {
  std::optional<formats::Motion3File> motion3;  // kept to write every other field back
  std::optional<formats::SpineFile> spine;      // the same for a Spine skeleton
  int spine_animation = -1;  // with `spine`: the index of the animation `curves` holds
  CurveSet curves;
};

// A motion3.json text, or (`csv`) a CSV text (`frame,<id>,...`) at `csv_fps` frames per
// second. Errors are the readers' own (formats/motion3.h, formats/curve_csv.h), without a
// file name: the caller prefixes the path or the request field.
absl::StatusOr<CurveInput> ParseCurveText(std::string_view text, bool csv, double csv_fps);

// A Spine skeleton JSON text, with the bone timelines of the animation named `animation` as
// the curves (empty name: the only animation with bone timelines; INVALID_ARGUMENT naming them
// when there are several, or none). Errors are ParseSpine's, and for the name NOT_FOUND listing
// the animations, or INVALID_ARGUMENT when it has no bone timelines to retime.
absl::StatusOr<CurveInput> ParseSpineText(std::string_view text, std::string_view animation);
// The same on a parsed file: only the animation's errors.
absl::StatusOr<CurveInput> SpineCurveInput(formats::SpineFile file, std::string_view animation);

// `input` (a Spine input) with its animation `index`'s curves in `curves`.
absl::Status SelectSpineAnimation(CurveInput& input, int index);

// A retimed curve: per-frame values and the same as stepped keyframes.
struct CurveReplacement {
  std::vector<double> values;
  std::vector<CurvePoint> steps;
};

// `input` with replacements[i] (when set) in place of curve i: as CSV (every curve, the others
// sampled at every frame) when `csv`, else as motion3.json (needs a motion3 input; the others
// untouched, Meta counts recomputed) or, for a Spine input, as its Spine JSON with the
// animation's timelines replaced (formats::WriteSpine). INVALID_ARGUMENT for motion3 output of
// a CSV input.
absl::StatusOr<std::string> CurveOutputText(
    const CurveInput& input, const std::vector<std::optional<CurveReplacement>>& replacements,
    bool csv);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_CURVE_TEXT_H_

#include "convert/curve_text.h"

#include <utility>

#include "formats/curve_csv.h"

namespace koma::convert {

absl::StatusOr<CurveInput> ParseCurveText(std::string_view text, bool csv, double csv_fps) {
  CurveInput input;
  if (csv) {
    absl::StatusOr<CurveSet> set = formats::ParseCurveCsv(text, csv_fps);
    if (!set.ok()) return set.status();
    input.curves = *std::move(set);
    return input;
  }
  absl::StatusOr<formats::Motion3File> file = formats::ParseMotion3(text);
  if (!file.ok()) return file.status();
  input.curves = file->curves;
  input.motion3 = *std::move(file);
  return input;
}

absl::StatusOr<std::string> CurveOutputText(
    const CurveInput& input, const std::vector<std::optional<CurveReplacement>>& replacements,
    bool csv) {
  const CurveSet& set = input.curves;
  if (csv) {
    std::vector<std::string> ids;
    std::vector<std::vector<double>> values;
    for (size_t i = 0; i < set.curves.size(); ++i) {
      ids.push_back(set.curves[i].id);
      values.push_back(replacements[i] ? replacements[i]->values
                                       : SampleEveryFrame(set.curves[i], set.frame_count,
                                                          set.beziers_restricted));
    }
    return formats::WriteCurveCsv(ids, values);
  }
  if (!input.motion3) {
    return absl::InvalidArgumentError("a CSV input can only be written as CSV");
  }
  std::vector<std::optional<std::vector<CurvePoint>>> stepped;
  for (const std::optional<CurveReplacement>& r : replacements) {
    stepped.push_back(r ? std::optional<std::vector<CurvePoint>>(r->steps) : std::nullopt);
  }
  return formats::WriteMotion3(*input.motion3, stepped);
}

}  // namespace koma::convert

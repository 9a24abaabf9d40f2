#include "client/curve_files.h"

#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/files.h"
#include "formats/curve_csv.h"

namespace koma::client {

bool IsCsvPath(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".csv"); }

bool CanWriteOutput(const std::string& input, const std::string& output) {
  if (IsCsvPath(output) || !IsCsvPath(input)) return true;
  std::fprintf(stderr, "koma: -o %s: a CSV input can only be written as CSV (-o OUT.csv)\n",
               output.c_str());
  return false;
}

absl::StatusOr<CurveInput> ReadCurveInput(const std::string& path, double csv_fps) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  CurveInput input;
  if (IsCsvPath(path)) {
    absl::StatusOr<CurveSet> set = formats::ParseCurveCsv(*text, csv_fps);
    if (!set.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(path, ": ", set.status().message()));
    }
    input.curves = *std::move(set);
    return input;
  }
  absl::StatusOr<formats::Motion3File> file = formats::ParseMotion3(*text);
  if (!file.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": ", file.status().message()));
  }
  input.curves = file->curves;
  input.motion3 = *std::move(file);
  return input;
}

absl::Status WriteCurveOutput(const std::string& path, const CurveInput& input,
                              const std::vector<std::optional<CurveReplacement>>& replacements) {
  const CurveSet& set = input.curves;
  if (IsCsvPath(path)) {
    std::vector<std::string> ids;
    std::vector<std::vector<double>> values;
    for (size_t i = 0; i < set.curves.size(); ++i) {
      ids.push_back(set.curves[i].id);
      values.push_back(replacements[i] ? replacements[i]->values
                                       : SampleEveryFrame(set.curves[i], set.frame_count,
                                                          set.beziers_restricted));
    }
    return WriteFile(path, formats::WriteCurveCsv(ids, values));
  }
  if (!input.motion3) {
    return absl::InvalidArgumentError(
        absl::StrCat("-o ", path, ": a CSV input can only be written as CSV (-o OUT.csv)"));
  }
  std::vector<std::optional<std::vector<CurvePoint>>> stepped;
  for (const std::optional<CurveReplacement>& r : replacements) {
    stepped.push_back(r ? std::optional<std::vector<CurvePoint>>(r->steps) : std::nullopt);
  }
  absl::StatusOr<std::string> text = formats::WriteMotion3(*input.motion3, stepped);
  if (!text.ok()) return text.status();
  return WriteFile(path, *text);
}

}  // namespace koma::client

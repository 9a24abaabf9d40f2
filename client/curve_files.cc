#include "client/curve_files.h"

#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/files.h"

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
  absl::StatusOr<CurveInput> input = convert::ParseCurveText(*text, IsCsvPath(path), csv_fps);
  if (!input.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": ", input.status().message()));
  }
  return input;
}

absl::Status WriteCurveOutput(const std::string& path, const CurveInput& input,
                              const std::vector<std::optional<CurveReplacement>>& replacements) {
  if (!IsCsvPath(path) && !input.motion3) {
    return absl::InvalidArgumentError(
        absl::StrCat("-o ", path, ": a CSV input can only be written as CSV (-o OUT.csv)"));
  }
  absl::StatusOr<std::string> text = convert::CurveOutputText(input, replacements, IsCsvPath(path));
  if (!text.ok()) return text.status();
  return WriteFile(path, *text);
}

}  // namespace koma::client

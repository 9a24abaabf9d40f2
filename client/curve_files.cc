#include "client/curve_files.h"

#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/file_format.h"
#include "client/files.h"
#include "formats/curve_csv.h"

namespace koma::client {
namespace {

std::string DisplayName(const std::string& path) { return IsStdio(path) ? "standard input" : path; }

}  // namespace

CurveFormat CurveFormatFromFlag(const std::string& value) {
  if (value == "motion3") return CurveFormat::kMotion3;
  if (value == "csv") return CurveFormat::kCsv;
  return CurveFormat::kAuto;
}

bool IsCsvPath(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".csv"); }

bool CanWriteOutput(const std::string& input, const std::string& output) {
  if (IsCsvPath(output) || !IsCsvPath(input)) return true;
  std::fprintf(stderr, "koma: -o %s: a CSV input can only be written as CSV (-o OUT.csv)\n",
               output.c_str());
  return false;
}

absl::StatusOr<CurveInput> ReadCurveInput(const std::string& path, double csv_fps,
                                          CurveFormat format, absl::string_view command) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  if (absl::Status s = CheckInputFormat(path, *text, command); !s.ok()) return s;
  if (format == CurveFormat::kAuto) {
    switch (SniffFormat(*text)) {
      case FileFormat::kMotion3:
        format = CurveFormat::kMotion3;
        break;
      case FileFormat::kCsv:
        format = CurveFormat::kCsv;
        break;
      default:
        format = IsCsvPath(path) ? CurveFormat::kCsv : CurveFormat::kMotion3;
    }
  }
  CurveInput input;
  input.format = format;
  if (format == CurveFormat::kCsv) {
    absl::StatusOr<CurveSet> set = formats::ParseCurveCsv(*text, csv_fps);
    if (!set.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(DisplayName(path), " (CSV): ", set.status().message()));
    }
    input.curves = *std::move(set);
    return input;
  }
  absl::StatusOr<formats::Motion3File> file = formats::ParseMotion3(*text);
  if (!file.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(DisplayName(path), " (motion3.json): ", file.status().message()));
  }
  input.curves = file->curves;
  input.motion3 = *std::move(file);
  return input;
}

absl::StatusOr<CurveFormat> CurveOutputFormat(const std::string& path, CurveFormat format,
                                              const CurveInput& input) {
  if (format == CurveFormat::kAuto) {
    if (absl::EndsWithIgnoreCase(path, ".bvh")) {
      return absl::InvalidArgumentError(
          absl::StrCat("-o ", path, ": curves are written as motion3.json or CSV, not BVH"));
    }
    format = IsCsvPath(path) ? CurveFormat::kCsv
             : IsStdio(path) ? input.format
                             : CurveFormat::kMotion3;
  }
  if (format == CurveFormat::kMotion3 && !input.motion3) {
    return absl::InvalidArgumentError(
        absl::StrCat("-o ", path, ": a CSV input can only be written as CSV (-o OUT.csv)"));
  }
  return format;
}

absl::Status WriteCurveOutput(const std::string& path, const CurveInput& input,
                              const std::vector<std::optional<CurveReplacement>>& replacements,
                              CurveFormat format) {
  absl::StatusOr<CurveFormat> resolved = CurveOutputFormat(path, format, input);
  if (!resolved.ok()) return resolved.status();
  const CurveSet& set = input.curves;
  if (*resolved == CurveFormat::kCsv) {
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
  std::vector<std::optional<std::vector<CurvePoint>>> stepped;
  for (const std::optional<CurveReplacement>& r : replacements) {
    stepped.push_back(r ? std::optional<std::vector<CurvePoint>>(r->steps) : std::nullopt);
  }
  absl::StatusOr<std::string> text = formats::WriteMotion3(*input.motion3, stepped);
  if (!text.ok()) return text.status();
  return WriteFile(path, *text);
}

}  // namespace koma::client

#include "client/curve_files.h"

#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/command_io.h"
#include "client/file_format.h"
#include "client/files.h"
#include "formats/spine.h"

namespace koma::client {
CurveFormat CurveFormatFromFlag(const std::string& value) {
  if (value == "motion3") return CurveFormat::kMotion3;
  if (value == "csv") return CurveFormat::kCsv;
  return CurveFormat::kAuto;
}

bool IsCsvPath(const std::string& path) { return FormatFromName(path) == FormatId::kCsv; }

bool CanWriteOutput(const std::string& input, const std::string& output) {
  if (IsCsvPath(output) || !IsCsvPath(input)) return true;
  PrintStderr(
      absl::StrCat("koma: -o ", output, ": a CSV input can only be written as CSV (-o OUT.csv)\n"));
  return false;
}

absl::StatusOr<CurveInput> ReadCurveInput(const std::string& path, double csv_fps,
                                          CurveFormat format, absl::string_view command) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  if (absl::Status s = CheckInputFormat(path, *text, command); !s.ok()) return s;
  if (absl::EndsWithIgnoreCase(path, ".skel")) {
    return absl::InvalidArgumentError(absl::StrCat(
        path, " is a binary Spine skeleton: koma reads Spine JSON (export the skeleton as JSON)"));
  }
  if (format != CurveFormat::kCsv && formats::IsSpineJson(*text)) {
    if (command != "curves" && command != kLipBlinkSpineCommand) {
      return absl::InvalidArgumentError(absl::StrCat(
          InputName(path), " is a Spine skeleton: `koma ", command,
          "` reads Live2D motion3.json or per-frame CSV",
          command == "lipblink" ? "; key a skeleton's mouth and eyes with --animation NAME and "
                                  "--mouth-slot SLOT / --eye-slot SLOT"
                                : "",
          "; retime Spine animations with `koma curves`"));
    }
    absl::StatusOr<formats::SpineFile> spine = formats::ParseSpine(*text);
    if (!spine.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(InputName(path), " (Spine JSON): ", spine.status().message()));
    }
    CurveInput input;
    input.spine = *std::move(spine);
    input.format = CurveFormat::kMotion3;  // JSON; the commands check `spine` first
    input.text = *std::move(text);
    return input;
  }
  if (format == CurveFormat::kAuto) {
    switch (SniffFormat(*text)) {
      case FormatId::kMotion3:
        format = CurveFormat::kMotion3;
        break;
      case FormatId::kCsv:
        format = CurveFormat::kCsv;
        break;
      default:
        format = IsCsvPath(path) ? CurveFormat::kCsv : CurveFormat::kMotion3;
    }
  }
  const bool csv = format == CurveFormat::kCsv;
  absl::StatusOr<convert::CurveInput> parsed = convert::ParseCurveText(*text, csv, csv_fps);
  if (!parsed.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(
        InputName(path), csv ? " (CSV): " : " (motion3.json): ", parsed.status().message()));
  }
  CurveInput input;
  static_cast<convert::CurveInput&>(input) = *std::move(parsed);
  input.format = format;
  input.text = *std::move(text);
  return input;
}

absl::StatusOr<CurveFormat> CurveOutputFormat(const std::string& path, CurveFormat format,
                                              const CurveInput& input) {
  if (format == CurveFormat::kAuto) {
    if (FormatFromName(path) == FormatId::kBvh) {
      return absl::InvalidArgumentError(
          absl::StrCat("-o ", path, ": curves are written as motion3.json or CSV, not BVH"));
    }
    format = IsCsvPath(path) ? CurveFormat::kCsv
             : IsStdio(path) ? input.format
                             : CurveFormat::kMotion3;
  }
  if (format == CurveFormat::kMotion3 && !input.motion3 && !input.spine) {
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
  absl::StatusOr<std::string> text =
      convert::CurveOutputText(input, replacements, *resolved == CurveFormat::kCsv);
  if (!text.ok()) return text.status();
  return WriteFile(path, *text);
}

}  // namespace koma::client

#include "client/file_format.h"

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/files.h"
#include "formats/text_encoding.h"

namespace koma::client {

FileFormat FormatFromName(const std::string& path) {
  if (absl::EndsWithIgnoreCase(path, ".bvh")) return FileFormat::kBvh;
  if (absl::EndsWithIgnoreCase(path, ".json")) return FileFormat::kMotion3;
  if (absl::EndsWithIgnoreCase(path, ".csv")) return FileFormat::kCsv;
  if (absl::EndsWithIgnoreCase(path, ".fbx")) return FileFormat::kFbx;
  for (absl::string_view ext : {".glb", ".gltf", ".vrm", ".vrma"}) {
    if (absl::EndsWithIgnoreCase(path, ext)) return FileFormat::kGltf;
  }
  return FileFormat::kUnknown;
}

FileFormat SniffFormat(absl::string_view text) {
  if (absl::StartsWith(text, "glTF")) return FileFormat::kGltf;
  if (absl::StartsWith(text, "Kaydara FBX Binary") || absl::StartsWith(text, "; FBX")) {
    return FileFormat::kFbx;
  }
  const absl::string_view bom(formats::kUtf8Bom.data(), formats::kUtf8Bom.size());
  if (absl::StartsWith(text, bom)) text.remove_prefix(bom.size());
  text = absl::StripLeadingAsciiWhitespace(text);
  if (absl::StartsWith(text, "HIERARCHY")) return FileFormat::kBvh;
  if (absl::StartsWith(text, "{")) {
    const bool gltf =
        absl::StrContains(text, "\"asset\"") && !absl::StrContains(text, "\"Curves\"");
    return gltf ? FileFormat::kGltf : FileFormat::kMotion3;
  }
  for (absl::string_view header : {"frame,", "frame;", "\"frame\",", "\"frame\";"}) {
    if (absl::StartsWith(text, header)) return FileFormat::kCsv;
  }
  return FileFormat::kUnknown;
}

absl::string_view FormatName(FileFormat format) {
  switch (format) {
    case FileFormat::kBvh:
      return "BVH";
    case FileFormat::kMotion3:
      return "motion3.json";
    case FileFormat::kCsv:
      return "CSV";
    case FileFormat::kGltf:
      return "glTF";
    case FileFormat::kFbx:
      return "FBX";
    case FileFormat::kUnknown:
      break;
  }
  return "unknown";
}

absl::Status CheckInputFormat(const std::string& path, absl::string_view text,
                              absl::string_view command) {
  const FileFormat found = SniffFormat(text);
  const bool skeletal = command == "skeletal";
  if (skeletal && (found == FileFormat::kMotion3 || found == FileFormat::kCsv)) {
    return absl::InvalidArgumentError(absl::StrCat(
        InputName(path), " is a ", FormatName(found),
        " file, not BVH, glTF or FBX: `koma skeletal` reads BVH motion capture, glTF 2.0 / VRM "
        "and binary FBX; "
        "retime curves with `koma curves` or `koma lipblink`"));
  }
  if (!skeletal &&
      (found == FileFormat::kBvh || found == FileFormat::kGltf || found == FileFormat::kFbx)) {
    return absl::InvalidArgumentError(absl::StrCat(
        InputName(path), " is a ", FormatName(found), " file, not motion3.json or CSV: `koma ",
        command, "` reads Live2D motion3.json or per-frame CSV; retime ",
        found == FileFormat::kBvh    ? "BVH clips"
        : found == FileFormat::kGltf ? "glTF files"
                                     : "FBX takes",
        " with `koma skeletal`"));
  }
  return absl::OkStatus();
}

}  // namespace koma::client

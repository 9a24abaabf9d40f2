// Which kind of file a text is, so a file given to the wrong command is named as such
// ("x.bvh is a BVH file, ...") instead of failing deep in the wrong parser.
#ifndef KOMA_CLIENT_FILE_FORMAT_H_
#define KOMA_CLIENT_FILE_FORMAT_H_

#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"

namespace koma::client {

enum class FileFormat { kUnknown, kBvh, kMotion3, kCsv, kGltf, kFbx };

// From the name: *.bvh, *.json (motion3.json), *.csv, *.glb, *.gltf, *.vrm, *.vrma (glTF),
// *.fbx, any case; kUnknown for "-" and others.
FileFormat FormatFromName(const std::string& path);

// From the first bytes (after a UTF-8 byte order mark and white space): the GLB magic "glTF"
// is glTF, "Kaydara FBX Binary" or an ASCII FBX's "; FBX" comment is FBX, "HIERARCHY" is BVH, "{" is JSON (glTF when it has an "asset" member and no
// "Curves", else motion3), "frame," or "frame;" (a CSV header, quoted or not) is CSV; else
// kUnknown.
FileFormat SniffFormat(absl::string_view text);

// "BVH", "motion3.json", "CSV", "glTF", "FBX", "unknown".
absl::string_view FormatName(FileFormat format);

// OK when `text` (read from `path`) is not recognisably of another format than `accepted`
// says; else INVALID_ARGUMENT such as "x.bvh is a BVH file, not motion3.json or CSV: `koma
// curves` reads Live2D motion3.json or per-frame CSV; retime BVH clips with `koma skeletal`".
// `command` is "skeletal", "curves" or "lipblink".
absl::Status CheckInputFormat(const std::string& path, absl::string_view text,
                              absl::string_view command);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILE_FORMAT_H_

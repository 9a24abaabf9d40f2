// A file given to the wrong command is named as such ("x.bvh is a BVH file, ...") instead of
// failing deep in the wrong parser. Which format a file is, and which commands read it, is
// formats/format_table.h's.
#ifndef KOMA_CLIENT_FILE_FORMAT_H_
#define KOMA_CLIENT_FILE_FORMAT_H_

#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "formats/format_table.h"

namespace koma::client {

using formats::FormatId;

// FormatFromName and SniffFormat (formats/format_table.h) on a path and a file's text.
FormatId FormatFromName(const std::string& path);
FormatId SniffFormat(absl::string_view text);

// OK when `text` (read from `path`) is not recognisably of a format that `command` does not
// take as its IN; else INVALID_ARGUMENT such as "x.bvh is a BVH file, not motion3.json or CSV:
// `koma curves` reads Live2D motion3.json or per-frame CSV; retime BVH clips with `koma
// skeletal`", every part of it from the format table. `command` is "skeletal", "curves" or
// "lipblink", possibly followed by the flags it runs with ("lipblink --animation").
absl::Status CheckInputFormat(const std::string& path, absl::string_view text,
                              absl::string_view command);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILE_FORMAT_H_

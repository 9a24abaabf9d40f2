// The encoding at the start of a text file. koma reads its text formats (BVH, motion3.json,
// curve CSV, and the CLI's TOML config and @LIST files) as UTF-8. Windows tools (Notepad,
// Excel's "CSV UTF-8", several exporters) start UTF-8 files with a byte order mark, EF BB BF,
// which is skipped wherever koma reads text. UTF-16 and UTF-32, with or without a byte order
// mark, are refused with a message that names the encoding, instead of a parse error on what
// looks like garbage.
#ifndef KOMA_FORMATS_TEXT_ENCODING_H_
#define KOMA_FORMATS_TEXT_ENCODING_H_

#include <string_view>

#include "absl/status/statusor.h"

namespace koma::formats {

// The UTF-8 encoding of U+FEFF, the byte order mark.
inline constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

// `text` without one leading UTF-8 byte order mark (unchanged when there is none).
// INVALID_ARGUMENT naming the encoding, e.g.
//   the file is UTF-16 (little-endian, byte order mark FF FE), not UTF-8: save it as UTF-8
// for a UTF-32 (00 00 FE FF, FF FE 00 00) or UTF-16 (FE FF, FF FE) byte order mark, and for
// UTF-16 without one (a NUL byte in the first two, next to an ASCII character: "H\0I\0..." is
// little-endian, "\0H\0I..." big-endian; no koma text format holds a NUL).
absl::StatusOr<std::string_view> SkipUtf8Bom(std::string_view text);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_TEXT_ENCODING_H_

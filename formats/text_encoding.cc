#include "formats/text_encoding.h"

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace koma::formats {
namespace {

absl::Status NotUtf8(const char* encoding) {
  return absl::InvalidArgumentError(
      absl::StrCat("the file is ", encoding, ", not UTF-8: save it as UTF-8"));
}

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

// A printable ASCII byte, tab, CR or LF: what the first character of a koma text file is.
bool AsciiText(char c) { return (c >= 0x20 && c < 0x7F) || c == '\t' || c == '\r' || c == '\n'; }

}  // namespace

absl::StatusOr<std::string_view> SkipUtf8Bom(std::string_view text) {
  using namespace std::string_view_literals;
  if (StartsWith(text, kUtf8Bom)) return text.substr(kUtf8Bom.size());
  // UTF-32 first: its little-endian mark begins with UTF-16's.
  if (StartsWith(text, "\xFF\xFE\0\0"sv)) {
    return NotUtf8("UTF-32 (little-endian, byte order mark FF FE 00 00)");
  }
  if (StartsWith(text, "\0\0\xFE\xFF"sv)) {
    return NotUtf8("UTF-32 (big-endian, byte order mark 00 00 FE FF)");
  }
  if (StartsWith(text, "\xFF\xFE"sv)) return NotUtf8("UTF-16 (little-endian, byte order mark FF FE)");
  if (StartsWith(text, "\xFE\xFF"sv)) return NotUtf8("UTF-16 (big-endian, byte order mark FE FF)");
  if (text.size() >= 2) {
    if (AsciiText(text[0]) && text[1] == '\0') {
      return NotUtf8("UTF-16 (little-endian, no byte order mark)");
    }
    if (text[0] == '\0' && AsciiText(text[1])) {
      return NotUtf8("UTF-16 (big-endian, no byte order mark)");
    }
  }
  return text;
}

}  // namespace koma::formats

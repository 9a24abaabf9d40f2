#include "formats/error_text.h"

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"

namespace koma::formats {

std::string QuoteForError(std::string_view text) {
  const bool cut = text.size() > kMaxQuotedBytes;
  const std::string_view shown = cut ? text.substr(0, kMaxQuotedBytes) : text;
  // Debian's abseil has its own absl::string_view, distinct from std::string_view.
  return absl::StrCat("\"", absl::CEscape(absl::string_view(shown.data(), shown.size())), "\"",
                      cut ? "..." : "");
}

}  // namespace koma::formats

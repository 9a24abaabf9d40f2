// Helpers for error messages about file contents.
#ifndef KOMA_FORMATS_ERROR_TEXT_H_
#define KOMA_FORMATS_ERROR_TEXT_H_

#include <string>
#include <string_view>

namespace koma::formats {

// Longest piece of input quoted in an error message, in bytes: a 1 MB token in a broken
// file must not become a 1 MB message.
inline constexpr size_t kMaxQuotedBytes = 40;

// `text` in double quotes for an error message: C-escaped (control bytes and quotes
// visible) and cut to kMaxQuotedBytes with "..." after the closing quote when longer.
// "Xrot" -> "\"Xrot\"".
std::string QuoteForError(std::string_view text);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_ERROR_TEXT_H_

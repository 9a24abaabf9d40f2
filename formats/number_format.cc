#include "formats/number_format.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "formats/error_text.h"

namespace koma::formats {
namespace {

// Below this magnitude the fixed form needs more than 6 leading zeros; at or above the upper
// bound it would print digits beyond the 17 significant ones a double holds.
constexpr double kMinFixedMagnitude = 1e-6;
constexpr double kMaxFixedMagnitude = 1e16;

// Enough for any shortest fixed form in the range above and any shortest exponent form
// (at most 24 characters, e.g. "-2.2250738585072014e-308").
constexpr size_t kBufferSize = 64;

absl::Status NotANumber(std::string_view text, const std::string& why) {
  return absl::InvalidArgumentError(
      absl::StrCat("invalid number ", QuoteForError(text), ": ", why));
}

}  // namespace

std::string FormatDouble(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0";  // both +0 and -0
  const double magnitude = std::fabs(value);
  const bool fixed = magnitude >= kMinFixedMagnitude && magnitude < kMaxFixedMagnitude;
  std::array<char, kBufferSize> buffer;
  char* const first = buffer.data();
  char* const last = buffer.data() + buffer.size();
  // Without a precision both overloads write the shortest text that reads back exactly.
  const std::to_chars_result result =
      fixed ? std::to_chars(first, last, value, std::chars_format::fixed)
            : std::to_chars(first, last, value);
  // The buffer is large enough for every finite double in either branch.
  return std::string(first, result.ptr);
}

absl::StatusOr<double> ParseDouble(std::string_view text) {
  if (text.empty()) return NotANumber(text, "empty");
  std::string_view digits = text;
  // std::from_chars accepts a leading '-' but not '+'; strip a '+' and make sure no second
  // sign follows it ("+-1").
  if (digits.front() == '+') {
    digits.remove_prefix(1);
    if (!digits.empty() && digits.front() == '-') return NotANumber(text, "two signs");
  }
  // from_chars would read "inf", "nan" and "infinity"; only a digit or '.' may start a number.
  const size_t first = (!digits.empty() && digits.front() == '-') ? 1 : 0;
  if (digits.size() <= first ||
      !(std::isdigit(static_cast<unsigned char>(digits[first])) || digits[first] == '.')) {
    return NotANumber(text, "not a decimal number");
  }
  double value = 0.0;
  const char* end = digits.data() + digits.size();
  const std::from_chars_result result =
      std::from_chars(digits.data(), end, value, std::chars_format::general);
  if (result.ec == std::errc::result_out_of_range) {
    return NotANumber(text, "outside the range of a double");
  }
  if (result.ec != std::errc()) return NotANumber(text, "not a decimal number");
  if (result.ptr != end) {
    const std::string_view rest(result.ptr, static_cast<size_t>(end - result.ptr));
    return NotANumber(text, absl::StrCat("unexpected ", QuoteForError(rest), " after the number"));
  }
  return value;
}

}  // namespace koma::formats

#include "client/flag_values.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"

namespace koma::client {
namespace {

absl::Status FlagError(absl::string_view flag, const std::string& message) {
  return absl::InvalidArgumentError(absl::StrCat(flag, ": ", message));
}

std::string Quoted(absl::string_view text) { return "\"" + std::string(text) + "\""; }

// Shortest decimal form ("1", "0.5", "1e+300").
std::string Number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

bool AllDigits(absl::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), absl::ascii_isdigit);
}

}  // namespace

absl::StatusOr<int64_t> ParseWholeNumber(absl::string_view flag, absl::string_view text,
                                         int64_t min, int64_t max) {
  absl::string_view digits = text;
  const bool negative = absl::ConsumePrefix(&digits, "-");
  if (!negative) absl::ConsumePrefix(&digits, "+");
  if (!AllDigits(digits)) {
    return FlagError(flag, absl::StrCat(Quoted(text), " is not a whole number"));
  }
  const std::string range = absl::StrCat("a whole number from ", min, " to ", max);
  uint64_t magnitude = 0;
  const auto [end, error] =
      std::from_chars(digits.data(), digits.data() + digits.size(), magnitude);
  (void)end;
  const bool huge = error == std::errc::result_out_of_range ||
                    magnitude > static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
  if (huge) {
    return FlagError(flag,
                     absl::StrCat(text, " is too ", negative ? "small" : "large", ": ", range));
  }
  const int64_t value =
      negative ? -static_cast<int64_t>(magnitude) : static_cast<int64_t>(magnitude);
  if (value < min) {
    return FlagError(flag, absl::StrCat(text, " is too small: the smallest allowed is ", min));
  }
  if (value > max) {
    return FlagError(flag, absl::StrCat(text, " is too large: the largest allowed is ", max));
  }
  return value;
}

absl::StatusOr<uint64_t> ParseUnsigned64(absl::string_view flag, absl::string_view text) {
  const std::string range =
      absl::StrCat("a whole number from 0 to ", std::numeric_limits<uint64_t>::max());
  absl::string_view digits = text;
  if (absl::ConsumePrefix(&digits, "-")) {
    if (AllDigits(digits)) return FlagError(flag, absl::StrCat(text, " is negative: ", range));
    return FlagError(flag, absl::StrCat(Quoted(text), " is not a whole number"));
  }
  absl::ConsumePrefix(&digits, "+");
  if (!AllDigits(digits)) {
    return FlagError(flag, absl::StrCat(Quoted(text), " is not a whole number"));
  }
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  (void)end;
  if (error == std::errc::result_out_of_range) {
    return FlagError(flag, absl::StrCat(text, " is too large: ", range));
  }
  return value;
}

NumberBounds AtLeast(double min) { return NumberBounds{min}; }
NumberBounds Above(double min) {
  NumberBounds b{min};
  b.min_open = true;
  return b;
}
NumberBounds OpenInterval(double min, double max) { return NumberBounds{min, max, true, true}; }

std::string DescribeBounds(const NumberBounds& b) {
  const bool has_min = std::isfinite(b.min);
  const bool has_max = std::isfinite(b.max);
  if (has_min && has_max) {
    if (b.min_open && b.max_open) {
      return absl::StrCat("between ", Number(b.min), " and ", Number(b.max), " (both excluded)");
    }
    if (!b.min_open && !b.max_open) {
      return absl::StrCat("from ", Number(b.min), " to ", Number(b.max));
    }
    return absl::StrCat(b.min_open ? "greater than " : "at least ", Number(b.min), " and ",
                        b.max_open ? "less than " : "at most ", Number(b.max));
  }
  if (has_min) return absl::StrCat(b.min_open ? "greater than " : "at least ", Number(b.min));
  if (has_max) return absl::StrCat(b.max_open ? "less than " : "at most ", Number(b.max));
  return "any finite number";
}

absl::StatusOr<double> ParseNumber(absl::string_view flag, absl::string_view text,
                                   const NumberBounds& bounds) {
  // strtod accepts what a person writes (1, 0.5, .5, 1e-3, +2) and also "nan", "inf" and hex
  // floats, which are refused below.
  const std::string copy(text);
  char* end = nullptr;
  errno = 0;
  const double value = copy.empty() ? 0.0 : std::strtod(copy.c_str(), &end);
  const bool hex = copy.find_first_of("xX") != std::string::npos;
  if (copy.empty() || end != copy.c_str() + copy.size() || hex ||
      absl::ascii_isspace(static_cast<unsigned char>(copy.front()))) {
    return FlagError(flag, absl::StrCat(Quoted(text), " is not a number"));
  }
  if (!std::isfinite(value)) {
    return FlagError(flag, absl::StrCat(Quoted(text), " is not a finite number"));
  }
  const bool below = bounds.min_open ? !(value > bounds.min) : !(value >= bounds.min);
  const bool above = bounds.max_open ? !(value < bounds.max) : !(value <= bounds.max);
  if (below || above) {
    return FlagError(flag,
                     absl::StrCat(text, " is out of range: must be ", DescribeBounds(bounds)));
  }
  return value;
}

absl::StatusOr<bool> ParseBool(absl::string_view flag, absl::string_view text) {
  const std::string lower = absl::AsciiStrToLower(text);
  if (lower == "true" || lower == "yes" || lower == "on" || lower == "1") return true;
  if (lower == "false" || lower == "no" || lower == "off" || lower == "0") return false;
  return FlagError(flag, absl::StrCat(Quoted(text), " is not true or false"));
}

absl::StatusOr<std::vector<double>> ParseNumberList(absl::string_view flag, absl::string_view text,
                                                    const NumberBounds& bounds, int count) {
  std::vector<double> values;
  if (!text.empty()) {
    for (absl::string_view part : absl::StrSplit(text, ',')) {
      absl::StatusOr<double> value = ParseNumber(flag, absl::StripAsciiWhitespace(part), bounds);
      if (!value.ok()) return value.status();
      values.push_back(*value);
    }
  }
  if (count > 0 && static_cast<int>(values.size()) != count) {
    return FlagError(
        flag, absl::StrCat("expected ", count, " comma-separated numbers, got ", values.size()));
  }
  return values;
}

absl::StatusOr<FlagInterval> ParseInterval(absl::string_view flag, absl::string_view text) {
  const std::vector<absl::string_view> parts = absl::StrSplit(text, absl::MaxSplits('-', 1));
  const std::string usage = absl::StrCat(
      Quoted(text), " is not a frame interval BEGIN-END (END one past the last frame, e.g. 10-25)");
  if (parts.size() != 2 || !AllDigits(parts[0]) || !AllDigits(parts[1])) {
    return FlagError(flag, usage);
  }
  absl::StatusOr<int64_t> begin = ParseWholeNumber(flag, parts[0], 0);
  if (!begin.ok()) return begin.status();
  absl::StatusOr<int64_t> end = ParseWholeNumber(flag, parts[1], 0);
  if (!end.ok()) return end.status();
  if (*end <= *begin) {
    return FlagError(flag, absl::StrCat(Quoted(text), ": END must be greater than BEGIN"));
  }
  return FlagInterval{static_cast<int32_t>(*begin), static_cast<int32_t>(*end)};
}

int EditDistance(absl::string_view a, absl::string_view b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string ClosestMatch(absl::string_view typed, const std::vector<std::string>& candidates) {
  std::string best;
  int best_distance = std::numeric_limits<int>::max();
  for (const std::string& candidate : candidates) {
    const int d = EditDistance(typed, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  const int allowed = std::max<int>(2, static_cast<int>(typed.size()) / 3);
  if (!best.empty() && best_distance <= allowed) return best;
  std::string prefixed;
  for (const std::string& candidate : candidates) {
    if (!typed.empty() && absl::StartsWith(candidate, typed)) {
      if (!prefixed.empty()) return "";
      prefixed = candidate;
    }
  }
  return prefixed;
}

}  // namespace koma::client

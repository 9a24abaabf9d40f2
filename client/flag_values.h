// Flag values parsed with messages a person can act on, e.g.
//   --omit: "abc" is not a whole number
//   --omit: -3 is too small: the smallest allowed is 0
//   --seed: -1 is negative: a seed is a whole number from 0 to 18446744073709551615
// Each message starts with the flag's name. Pure functions, no CLI11 (tested directly).
#ifndef KOMA_CLIENT_FLAG_VALUES_H_
#define KOMA_CLIENT_FLAG_VALUES_H_

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace koma::client {

// A whole number in [min, max] (decimal; a leading "+" or "-" allowed).
absl::StatusOr<int64_t> ParseWholeNumber(absl::string_view flag, absl::string_view text,
                                         int64_t min = std::numeric_limits<int32_t>::min(),
                                         int64_t max = std::numeric_limits<int32_t>::max());

// A whole number 0 .. 2^64 - 1 (a seed); a negative one is refused, never wrapped.
absl::StatusOr<uint64_t> ParseUnsigned64(absl::string_view flag, absl::string_view text);

// Bounds of a real-valued flag; an open bound excludes its value.
struct NumberBounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;
};
// Bounds helpers: AtLeast(1), Above(0), Between(0, 1, open, open).
NumberBounds AtLeast(double min);
NumberBounds Above(double min);
NumberBounds OpenInterval(double min, double max);
// "at least 1", "greater than 0", "between 0 and 1 (both excluded)", ...
std::string DescribeBounds(const NumberBounds& bounds);

// A finite decimal number within `bounds` ("nan", "inf", "1e999" are refused).
absl::StatusOr<double> ParseNumber(absl::string_view flag, absl::string_view text,
                                   const NumberBounds& bounds = {});

// true/false, yes/no, on/off, 1/0 (any case).
absl::StatusOr<bool> ParseBool(absl::string_view flag, absl::string_view text);

// Comma-separated numbers, each as ParseNumber; "" gives none. `count` > 0: exactly that many.
absl::StatusOr<std::vector<double>> ParseNumberList(absl::string_view flag, absl::string_view text,
                                                    const NumberBounds& bounds = {}, int count = 0);

// A frame interval "BEGIN-END" (half-open: END one past the last frame), 0 <= BEGIN < END.
struct FlagInterval {
  int32_t begin = 0;
  int32_t end = 0;
};
absl::StatusOr<FlagInterval> ParseInterval(absl::string_view flag, absl::string_view text);

// Levenshtein distance (insertions, deletions, substitutions each 1).
int EditDistance(absl::string_view a, absl::string_view b);

// The candidate closest to `typed` if it is close enough to be a likely typo (edit distance at
// most 2, or at most a third of its length for long names, or `typed` a prefix of exactly one
// candidate); "" otherwise.
std::string ClosestMatch(absl::string_view typed, const std::vector<std::string>& candidates);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FLAG_VALUES_H_

// Locale-independent number text for the file formats: the shortest decimal that reads back
// to the same double, and a strict parser for the numbers found in BVH and CSV files.
#ifndef KOMA_FORMATS_NUMBER_FORMAT_H_
#define KOMA_FORMATS_NUMBER_FORMAT_H_

#include <string>
#include <string_view>

#include "absl/status/statusor.h"

namespace koma::formats {

// The shortest text that ParseDouble reads back to exactly `value`, bit for bit, except that
// -0 is written as "0" (a signed zero means nothing in motion data, and "-0" reads like a
// bug). Magnitudes in [1e-6, 1e16) are written without an exponent ("0.0083333", "-12.5",
// "90"); others use the shortest exponent form ("1e-07", "1.5e+20"). NaN and infinities are
// written as "nan", "inf" and "-inf", which ParseDouble rejects.
std::string FormatDouble(double value);

// Parses a whole string as a finite double: an optional sign ('+' or '-'), digits with an
// optional '.' (".0083333", "5." and "-.5" are fine) and an optional exponent ("1e-3").
// INVALID_ARGUMENT quoting the text for an empty string, surrounding whitespace, trailing
// characters, hexadecimal, "nan"/"inf", or a value outside the range of a double (including
// underflow below the smallest subnormal, e.g. "1e-400").
absl::StatusOr<double> ParseDouble(std::string_view text);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_NUMBER_FORMAT_H_

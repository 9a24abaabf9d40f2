// One pass over many doubles that tells whether all are finite and which is largest in
// magnitude, for the validators that check every value of a request (a 100,000-frame clip has
// 7.4 million): a loop that returns at the first bad value cannot be vectorised, this one can.
#ifndef KOMA_CORE_MAGNITUDE_SCAN_H_
#define KOMA_CORE_MAGNITUDE_SCAN_H_

#include <cstdint>

#include "absl/types/span.h"

namespace koma {

// |x|'s bit pattern for the largest |x| in `values` (0 when empty). With the sign bit
// cleared, doubles order like their bit patterns, and +inf and every NaN lie above every
// finite value: a result of kNonFiniteBits or more means some value is not finite.
uint64_t LargestMagnitudeBits(absl::Span<const double> values);

inline constexpr uint64_t kNonFiniteBits = 0x7ff0000000000000ULL;  // +inf

inline bool AllFinite(absl::Span<const double> values) {
  return LargestMagnitudeBits(values) < kNonFiniteBits;
}

}  // namespace koma

#endif  // KOMA_CORE_MAGNITUDE_SCAN_H_

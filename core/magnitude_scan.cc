#include "core/magnitude_scan.h"

#include <cstring>

namespace koma {

// Built for plain x86-64 and for AVX2 (64-bit integer compares, 4 lanes), picked at load
// time; integer operations only, so every build gives the same answer.
__attribute__((target_clones("avx2", "default"))) uint64_t LargestMagnitudeBits(
    absl::Span<const double> values) {
  constexpr uint64_t kMagnitudeMask = 0x7fffffffffffffffULL;
  uint64_t largest = 0;
  for (double value : values) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    bits &= kMagnitudeMask;
    largest = bits > largest ? bits : largest;
  }
  return largest;
}

}  // namespace koma

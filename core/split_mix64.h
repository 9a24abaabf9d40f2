// SplitMix64 (Steele, Lea and Flood, 2014): koma's one pseudo-random generator. Its output is
// specified bit for bit, so the same seed gives the same numbers with every compiler and
// standard library; std::*_distribution is never used, because its output differs between
// standard libraries and a render farm needs identical answers on every node.
#ifndef KOMA_CORE_SPLIT_MIX64_H_
#define KOMA_CORE_SPLIT_MIX64_H_

#include <cstdint>

namespace koma {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}

  // The next 64 random bits.
  uint64_t Next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // An integer in [lo, hi], lo <= hi, by modulo: the bias is below 2^-40 for ranges under
  // 2^24, irrelevant here.
  int Int(int lo, int hi) {
    return lo + static_cast<int>(Next() % static_cast<uint64_t>(int64_t{hi} - lo + 1));
  }
  // A double in [0, 1) from the top 53 bits.
  double Unit() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  // True with probability 1/n.
  bool OneIn(int n) { return Int(1, n) == 1; }

 private:
  uint64_t state_;
};

}  // namespace koma

#endif  // KOMA_CORE_SPLIT_MIX64_H_

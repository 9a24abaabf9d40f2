#include "core/magnitude_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double FromBits(uint64_t bits) {
  double value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

// The literal form: the largest fabs, any non-finite value reported as such.
TEST(MagnitudeScanTest, AgreesWithTheLiteralScanOnRandomArrays) {
  SplitMix64 rng(5);
  const double specials[] = {0.0,   -0.0,  kInf,   -kInf,    kNaN,
                             -kNaN, 1e308, -1e308, 4.9e-324, std::numeric_limits<double>::max()};
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<double> values(static_cast<size_t>(rng.Int(0, 70)));
    for (double& v : values) {
      v = rng.Int(0, 9) == 0 ? specials[rng.Int(0, 9)] : (rng.Unit() - 0.5) * 1e6;
    }
    const bool all_finite =
        std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
    EXPECT_EQ(AllFinite(values), all_finite);
    if (all_finite) {
      double largest = 0.0;
      for (double v : values) largest = std::max(largest, std::fabs(v));
      EXPECT_EQ(FromBits(LargestMagnitudeBits(values)), largest);
    } else {
      EXPECT_GE(LargestMagnitudeBits(values), kNonFiniteBits);
    }
  }
}

TEST(MagnitudeScanTest, EmptyAndSignedZero) {
  EXPECT_EQ(LargestMagnitudeBits({}), 0u);
  const std::vector<double> zeros = {-0.0, 0.0};
  EXPECT_EQ(LargestMagnitudeBits(zeros), 0u);
  EXPECT_TRUE(AllFinite(zeros));
  const std::vector<double> last_bad = {1, 2, 3, 4, 5, 6, 7, kNaN};
  EXPECT_FALSE(AllFinite(last_bad));
}

}  // namespace
}  // namespace koma

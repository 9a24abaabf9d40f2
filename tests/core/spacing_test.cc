// HoldLengths and Spacing (docs/semantics.md, "RetimeCurves"): the hold rule, and tame/tsume
// spacing on hand-computed values and its defining properties (even, geometric, symmetric,
// increasing).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "core/koma_uchi.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

using ::testing::ElementsAre;

TEST(HoldLengthsTest, AsEvenAsPossibleLongerFirst) {
  EXPECT_THAT(HoldLengths(10, 3), ElementsAre(3, 3, 2, 2));
  EXPECT_THAT(HoldLengths(9, 3), ElementsAre(3, 3, 3));
  EXPECT_THAT(HoldLengths(7, 2), ElementsAre(2, 2, 2, 1));
  EXPECT_THAT(HoldLengths(1, 3), ElementsAre(1));
  EXPECT_THAT(HoldLengths(4, 1), ElementsAre(1, 1, 1, 1));
  EXPECT_THAT(HoldLengths(5, 1000000000), ElementsAre(5));
}

TEST(HoldLengthsTest, CeilLOverNHoldsNeverLongerThanNSummingToL) {
  for (int length = 1; length <= 120; ++length) {
    for (int n = 1; n <= 12; ++n) {
      const std::vector<int> holds = HoldLengths(length, n);
      ASSERT_EQ(static_cast<int>(holds.size()), (length + n - 1) / n) << length << "@" << n;
      EXPECT_EQ(std::accumulate(holds.begin(), holds.end(), 0), length);
      EXPECT_LE(holds.front(), n);
      EXPECT_LE(holds.front() - holds.back(), 1);
      EXPECT_TRUE(std::is_sorted(holds.rbegin(), holds.rend()));  // longer ones first
    }
  }
}

TEST(SpacingTest, EvenWhenBothStrengthsAreOneExactly) {
  EXPECT_THAT(Spacing(1, 1.0, 1.0), ElementsAre(0.0));
  for (int d = 1; d <= 40; ++d) {
    const std::vector<double> e = Spacing(d, 1.0, 1.0);
    ASSERT_EQ(static_cast<int>(e.size()), d);
    for (int j = 0; j < d; ++j) EXPECT_EQ(e[j], static_cast<double>(j) / d) << j << "/" << d;
  }
}

TEST(SpacingTest, HandComputedValues) {
  // D = 4, s = 2: h = 2, s^h - 1 = 3: E_1 = (2 - 1) / 6, E_2 = 1/2, E_3 = 1 - 1/6.
  const std::vector<double> four = Spacing(4, 2.0, 2.0);
  ASSERT_EQ(four.size(), 4u);
  EXPECT_EQ(four[0], 0.0);
  EXPECT_NEAR(four[1], 1.0 / 6, 1e-15);
  EXPECT_NEAR(four[2], 0.5, 1e-15);
  EXPECT_NEAR(four[3], 5.0 / 6, 1e-15);
  // D = 3, s = 4: h = 1.5, s^h = 8: E_1 = (4 - 1) / 14, E_2 = 1 - 3/14.
  const std::vector<double> three = Spacing(3, 4.0, 4.0);
  ASSERT_EQ(three.size(), 3u);
  EXPECT_NEAR(three[1], 3.0 / 14, 1e-15);
  EXPECT_NEAR(three[2], 11.0 / 14, 1e-15);
  // Only tsume: the first half is even (j / D), the second geometric: D = 6, s_b = 2, h = 3:
  // E_4 = 1 - (4 - 1) / 14, E_5 = 1 - (2 - 1) / 14.
  const std::vector<double> six = Spacing(6, 1.0, 2.0);
  ASSERT_EQ(six.size(), 6u);
  EXPECT_EQ(six[1], 1.0 / 6);
  EXPECT_EQ(six[3], 0.5);
  EXPECT_NEAR(six[4], 11.0 / 14, 1e-15);
  EXPECT_NEAR(six[5], 13.0 / 14, 1e-15);
  EXPECT_THAT(Spacing(2, 3.0, 5.0), ElementsAre(0.0, 0.5));
}

// Gaps g_j = E_{j+1} - E_j (E_D = 1, the next key): g_{j+1} / g_j = s_a while both gaps lie in
// the first half, 1 / s_b while both lie in the second.
TEST(SpacingTest, GapsGrowBySaThenShrinkBySb) {
  for (int d : {6, 7, 10, 11, 16}) {
    const double sa = 1.7;
    const double sb = 2.5;
    std::vector<double> e = Spacing(d, sa, sb);
    e.push_back(1.0);
    const int half = d / 2;
    for (int j = 0; j + 2 <= half; ++j) {
      const double ratio = (e[j + 2] - e[j + 1]) / (e[j + 1] - e[j]);
      EXPECT_NEAR(ratio, sa, 1e-12) << "D = " << d << " j = " << j;
    }
    for (int j = (d + 1) / 2; j + 2 <= d; ++j) {
      const double ratio = (e[j + 2] - e[j + 1]) / (e[j + 1] - e[j]);
      EXPECT_NEAR(ratio, 1.0 / sb, 1e-12) << "D = " << d << " j = " << j;
    }
  }
}

TEST(SpacingTest, SymmetricWhenTameEqualsTsume) {
  for (int d = 1; d <= 40; ++d) {
    const std::vector<double> e = Spacing(d, 2.5, 2.5);
    for (int j = 1; j < d; ++j) EXPECT_NEAR(e[j] + e[d - j], 1.0, 1e-12) << j << "/" << d;
    if (d % 2 == 0) {
      EXPECT_EQ(e[d / 2], 0.5);
    }
  }
}

TEST(SpacingTest, StrictlyIncreasingFromZeroBelowOneForRandomStrengths) {
  SplitMix64 rng(3);
  for (int trial = 0; trial < 2000; ++trial) {
    const int d = rng.Int(1, 40);
    const double sa = rng.OneIn(5) ? 1.0 : 1.0 + 3.0 * rng.Unit();
    const double sb = rng.OneIn(5) ? 1.0 : 1.0 + 3.0 * rng.Unit();
    const std::vector<double> e = Spacing(d, sa, sb);
    ASSERT_EQ(static_cast<int>(e.size()), d);
    EXPECT_EQ(e[0], 0.0);
    EXPECT_LT(e.back(), 1.0);
    for (int j = 1; j < d; ++j) {
      ASSERT_LT(e[j - 1], e[j]) << "D = " << d << " s_a = " << sa << " s_b = " << sb;
    }
  }
}

TEST(SpacingTest, LongSegmentsWithStrongTameStayFinite) {
  // 4^2500 overflows a double; the computation must not produce inf or NaN. (The ends are
  // within 4^-2499 of 0 and 1, closer than a double can tell, so only <= holds there.)
  const std::vector<double> e = Spacing(5000, 4.0, 4.0);
  for (size_t j = 1; j < e.size(); ++j) {
    ASSERT_TRUE(std::isfinite(e[j])) << j;
    ASSERT_LE(e[j - 1], e[j]) << j;
  }
  EXPECT_EQ(e[2500], 0.5);
  EXPECT_LE(e.back(), 1.0);
  EXPECT_NEAR(e[2501] - e[2500], 0.5 * 0.75, 1e-15);  // the middle gap, 1/2 (1 - 1/s_b)
}

}  // namespace
}  // namespace koma

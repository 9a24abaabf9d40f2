#include "core/trig_degrees.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/sin_whole_degrees.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr long double kPi = 3.14159265358979323846264338327950288L;

TEST(TrigDegreesTest, ExactAtMultiplesOfNinety) {
  const struct { double degrees, sin, cos; } cases[] = {
      {0, 0, 1},   {90, 1, 0},    {180, 0, -1}, {270, -1, 0}, {360, 0, 1},
      {-90, -1, 0}, {450, 1, 0}, {-720, 0, 1}, {1e6 * 360, 0, 1}};
  for (const auto& c : cases) {
    const SinCos sc = SinCosDegrees(c.degrees);
    EXPECT_EQ(sc.sin, c.sin) << c.degrees;
    EXPECT_EQ(sc.cos, c.cos) << c.degrees;
    EXPECT_FALSE(std::signbit(sc.sin) && sc.sin == 0.0) << "no -0 at " << c.degrees;
  }
}

TEST(TrigDegreesTest, CommonAnglesWithinAnUlpOfTheTruth) {
  EXPECT_NEAR(SinCosDegrees(30).sin, 0.5, 1e-16);
  EXPECT_NEAR(SinCosDegrees(45).sin, std::sqrt(0.5), 2e-16);
  EXPECT_NEAR(SinCosDegrees(60).cos, 0.5, 1e-16);
}

// Against long double libm (a reference more precise than double) on random angles: within
// 1.25e-16, about one ulp for values near 1 (2M angles measured: 1.12e-16 at most).
TEST(TrigDegreesTest, AgreesWithLibmToAFewUlps) {
  SplitMix64 rng(7);
  for (int i = 0; i < 200000; ++i) {
    const double degrees = (rng.Unit() - 0.5) * (i % 2 == 0 ? 720.0 : 1e5);
    const SinCos sc = SinCosDegrees(degrees);
    const long double radians =
        static_cast<long double>(std::fmod(degrees, 360.0)) * (kPi / 180.0L);
    ASSERT_NEAR(sc.sin, static_cast<double>(std::sin(radians)), 1.25e-16) << degrees;
    ASSERT_NEAR(sc.cos, static_cast<double>(std::cos(radians)), 1.25e-16) << degrees;
  }
}

// Every entry of the table is sin(n degrees) rounded to the nearest double, as long double
// libm (64-bit significand) rounds it, and the entries the sign and exactness rules rely on are
// exact.
TEST(TrigDegreesTest, TableOfWholeDegreesIsCorrectlyRounded) {
  using trig_internal::kSinWholeDegrees;
  for (int n = 0; n < trig_internal::kSinWholeDegreesSize; ++n) {
    if (n % 180 == 0) continue;  // exact 0 below; sinl(pi) is not, pi being rounded
    const long double exact = std::sin(static_cast<long double>(n % 360) * (kPi / 180.0L));
    EXPECT_EQ(kSinWholeDegrees[n], static_cast<double>(exact)) << n;
  }
  for (int n = 0; n <= 450; n += 90) {
    EXPECT_EQ(kSinWholeDegrees[n], (n / 90) % 2 == 0 ? 0.0 : (n % 360 == 90 ? 1.0 : -1.0)) << n;
  }
  EXPECT_EQ(kSinWholeDegrees[30], 0.5);
}

// A golden checksum of the bits over a fixed sweep: a compiler, flag or library that changes
// any bit of any result fails here, as the service's same-bytes promise requires. (Re-pinned on
// purpose twice: when the Taylor series gave way to minimax polynomials, then when those gave
// way to the table of whole degrees; each time the plain x86-64, x86-64-v2, AVX2 and AVX-512
// builds, and an -O0 one, were checked to give the same hashes.)
TEST(TrigDegreesTest, BitsArePinned) {
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a
  for (int i = -3600; i <= 3600; ++i) {
    const SinCos sc = SinCosDegrees(i * 0.1 + 0.0123);
    for (double v : {sc.sin, sc.cos}) {
      uint64_t bits;
      std::memcpy(&bits, &v, sizeof(bits));
      for (int b = 0; b < 8; ++b) {
        hash ^= (bits >> (8 * b)) & 0xff;
        hash *= 0x100000001b3ULL;
      }
    }
  }
  EXPECT_EQ(hash, 0x7550c880f60abddbULL) << std::hex << hash;
}

// The reduction's corner cases: the doubles next to every multiple of 45 degrees (where the
// quadrant or the complement changes) up to +-1440, and angles past 360 that need fmod. The
// reduction's bits were first pinned with a plain implementation (fmod always, quadrant by
// division); this hash is that reduction with the current polynomials.
TEST(TrigDegreesTest, BitsArePinnedAtQuadrantBoundaries) {
  uint64_t hash = 0xcbf29ce484222325ULL;  // FNV-1a
  const auto mix = [&hash](double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    for (int b = 0; b < 8; ++b) {
      hash ^= (bits >> (8 * b)) & 0xff;
      hash *= 0x100000001b3ULL;
    }
  };
  for (int k = -32; k <= 32; ++k) {
    double degrees = std::nextafter(45.0 * k, -1e9);
    degrees = std::nextafter(degrees, -1e9);
    for (int step = 0; step < 5; ++step) {  // two below, the multiple, two above
      const SinCos sc = SinCosDegrees(degrees);
      mix(sc.sin);
      mix(sc.cos);
      degrees = std::nextafter(degrees, 1e9);
    }
  }
  SplitMix64 rng(11);
  for (int i = 0; i < 1000; ++i) {
    const SinCos sc = SinCosDegrees((rng.Unit() - 0.5) * 1e7);
    mix(sc.sin);
    mix(sc.cos);
  }
  EXPECT_EQ(hash, 0x53044c4087c2f1efULL) << std::hex << hash;
}

}  // namespace
}  // namespace koma

#include "core/trig_degrees.h"

#include <cmath>

namespace koma {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

// Taylor series for |x| <= pi/4 radians in Horner form. The first omitted terms, x^19/19! and
// x^20/20!, are below 1e-19 there, far under half an ulp of the results.
inline double SinSeries(double x) {
  const double x2 = x * x;
  double p = 1.0 / 355687428096000.0;   // 1/17!
  p = -1.0 / 1307674368000.0 + x2 * p;  // 1/15!
  p = 1.0 / 6227020800.0 + x2 * p;      // 1/13!
  p = -1.0 / 39916800.0 + x2 * p;       // 1/11!
  p = 1.0 / 362880.0 + x2 * p;          // 1/9!
  p = -1.0 / 5040.0 + x2 * p;           // 1/7!
  p = 1.0 / 120.0 + x2 * p;             // 1/5!
  p = -1.0 / 6.0 + x2 * p;              // 1/3!
  return x + x * (x2 * p);
}

inline double CosSeries(double x) {
  const double x2 = x * x;
  double p = 1.0 / 6402373705728000.0;   // 1/18!
  p = -1.0 / 20922789888000.0 + x2 * p;  // 1/16!
  p = 1.0 / 87178291200.0 + x2 * p;      // 1/14!
  p = -1.0 / 479001600.0 + x2 * p;       // 1/12!
  p = 1.0 / 3628800.0 + x2 * p;          // 1/10!
  p = -1.0 / 40320.0 + x2 * p;           // 1/8!
  p = 1.0 / 720.0 + x2 * p;              // 1/6!
  p = -1.0 / 24.0 + x2 * p;              // 1/4!
  p = 0.5 + x2 * p;                      // 1/2!, sign folded below
  return 1.0 - x2 * p;
}

}  // namespace

SinCos SinCosDegrees(double degrees) {
  SinCos result;
  SinCosDegrees(&degrees, 1, &result.sin, &result.cos);
  return result;
}

// Built twice, for plain x86-64 (SSE2: 2 lanes) and for AVX2 (4 lanes), picked at load time
// by the CPU. Same operations lane by lane, and -ffp-contract=off keeps multiply-adds
// unfused in both, so the bits are the same on every machine.
__attribute__((target_clones("avx2", "default")))
void SinCosDegrees(const double* degrees, int n, double* sin, double* cos) {
  // Reduce in degrees, where every step is exact: sin(-a) = -sin(a) and cos(-a) = cos(a)
  // take the sign off, fmod is exact by definition, and subtracting a multiple of 90 from a
  // value at most twice it is exact (Sterbenz). (Adding 360 to a negative angle would not be.)
  // First pass: |degrees| within one turn, into sin[] as scratch. fmod returns its argument
  // below 360, so the libm call is only made past a turn (rare: a separate, scalar loop).
  for (int i = 0; i < n; ++i) {
    const double magnitude = std::fabs(degrees[i]);
    sin[i] = magnitude < 360.0 ? magnitude : std::fmod(magnitude, 360.0);  // [0, 360)
  }
  // Second pass, branch-free (comparisons and selects only), so it vectorises.
  for (int i = 0; i < n; ++i) {
    const double r = sin[i];
    // The quadrant by comparisons rather than r / 90 (a division, and one that can round up
    // across a boundary); r - 90 q is then exact: 90 q >= r / 2 for q >= 1 (Sterbenz).
    const double quadrant =
        (r >= 90.0 ? 1.0 : 0.0) + (r >= 180.0 ? 1.0 : 0.0) + (r >= 270.0 ? 1.0 : 0.0);
    const double within = r - 90.0 * quadrant;  // [0, 90)
    // Past 45 degrees use the complement, so the series only sees |x| <= pi/4.
    // (Every operand is computed before a select picks one: a select that guards arithmetic
    // counts as control flow, and the loop would not vectorise.)
    const bool complement = within > 45.0;
    const double complement_angle = 90.0 - within;
    const double x = (complement ? complement_angle : within) * kRadiansPerDegree;
    const double series_sin = SinSeries(x);
    const double series_cos = CosSeries(x);
    // Quadrant q turns (s, c) into (s, c), (c, -s), (-s, -c), (-c, s) for q = 0..3;
    // negations are exact.
    const bool odd = (quadrant == 1.0) | (quadrant == 3.0);
    const bool swap = complement ^ odd;
    const double s = swap ? series_cos : series_sin;
    const double c = swap ? series_sin : series_cos;
    const bool sin_negative = (quadrant >= 2.0) ^ (degrees[i] < 0.0);
    const bool cos_negative = (quadrant == 1.0) | (quadrant == 2.0);
    // "+ 0.0" turns a -0 into +0.
    const double minus_s = -s;
    const double minus_c = -c;
    sin[i] = (sin_negative ? minus_s : s) + 0.0;
    cos[i] = (cos_negative ? minus_c : c) + 0.0;
  }
}

}  // namespace koma

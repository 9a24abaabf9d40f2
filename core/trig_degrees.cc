#include "core/trig_degrees.h"

#include <cmath>

namespace koma {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

// Polynomials for |x| <= pi/4 radians: sin x = x + x^3 P(x^2) and cos x = 1 - x^2 / 2 +
// x^4 Q(x^2), with P and Q of degree 5 fitted to minimise the largest relative error over that
// interval (the coefficients are Cephes' sin.c, by Stephen L. Moshier: error about 1e-17, well
// under half an ulp). Six terms each instead of a Taylor series' nine or ten: the chains of
// dependent multiply-adds are what limit the vectorised loop below.
inline double SinPolynomial(double x) {
  const double z = x * x;
  double p = 1.58962301576546568060e-10;
  p = -2.50507477628578072866e-8 + z * p;
  p = 2.75573136213857245213e-6 + z * p;
  p = -1.98412698295895385996e-4 + z * p;
  p = 8.33333333332211858878e-3 + z * p;
  p = -1.66666666666666307295e-1 + z * p;
  return x + x * (z * p);
}

inline double CosPolynomial(double x) {
  const double z = x * x;
  double q = -1.13585365213876817300e-11;
  q = 2.08757008419747316778e-9 + z * q;
  q = -2.75573141792967388112e-7 + z * q;
  q = 2.48015872888517045348e-5 + z * q;
  q = -1.38888888888730564116e-3 + z * q;
  q = 4.16666666666665929218e-2 + z * q;
  return (1.0 - 0.5 * z) + (z * z) * q;
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
__attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
void SinCosDegrees(const double* degrees, int n, double* sin, double* cos) {
  // Reduce in degrees, where every step is exact: sin(-a) = -sin(a) and cos(-a) = cos(a)
  // take the sign off, fmod is exact by definition, and subtracting a multiple of 90 from a
  // value at most twice it is exact (Sterbenz). (Adding 360 to a negative angle would not be.)
  // First pass: |degrees| into sin[] as scratch, counting those past a turn (a vectorised
  // loop: a libm call inside it would make it scalar, about a sixth of the whole time). Those
  // are rare, and only then does a second, scalar loop bring them within one turn, [0, 360).
  int past_a_turn = 0;
  for (int i = 0; i < n; ++i) {
    sin[i] = std::fabs(degrees[i]);
    past_a_turn += sin[i] >= 360.0;
  }
  if (past_a_turn > 0) {
    for (int i = 0; i < n; ++i) sin[i] = sin[i] < 360.0 ? sin[i] : std::fmod(sin[i], 360.0);
  }
  // Second pass, branch-free (comparisons and selects only), so it vectorises.
  for (int i = 0; i < n; ++i) {
    const double r = sin[i];
    // The quadrant by comparisons rather than r / 90 (a division, and one that can round up
    // across a boundary); r - 90 q is then exact: 90 q >= r / 2 for q >= 1 (Sterbenz).
    const double quadrant =
        (r >= 90.0 ? 1.0 : 0.0) + (r >= 180.0 ? 1.0 : 0.0) + (r >= 270.0 ? 1.0 : 0.0);
    const double within = r - 90.0 * quadrant;  // [0, 90)
    // Past 45 degrees use the complement, so the polynomials only see |x| <= pi/4.
    // (Every operand is computed before a select picks one: a select that guards arithmetic
    // counts as control flow, and the loop would not vectorise.)
    const bool complement = within > 45.0;
    const double complement_angle = 90.0 - within;
    const double x = (complement ? complement_angle : within) * kRadiansPerDegree;
    const double series_sin = SinPolynomial(x);
    const double series_cos = CosPolynomial(x);
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

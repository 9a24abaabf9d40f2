#include "core/trig_degrees.h"

#include <cmath>

#include "core/sin_whole_degrees.h"
#include "core/target_clones.h"

namespace koma {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

// Taylor series for |x| <= 0.5 degrees (0.0087 radians): sin x = x + x^3 (-1/6 + x^2 (1/120 -
// x^2 / 5040)) and cos x - 1 = x^2 (-1/2 + x^2 (1/24 - x^2 / 720)). The first terms left out,
// x^9 / 9! and x^8 / 8!, are below 1e-21 of sin x and of 1.
inline double SinSmall(double x) {
  const double z = x * x;
  return x + x * (z * (-1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0))));
}

inline double CosSmallMinusOne(double x) {
  const double z = x * x;
  return z * (-0.5 + z * (1.0 / 24.0 + z * (-1.0 / 720.0)));
}

}  // namespace

SinCos SinCosDegrees(double degrees) {
  SinCos result;
  SinCosDegrees(&degrees, 1, &result.sin, &result.cos);
  return result;
}

// Built for plain x86-64 (SSE2: 2 lanes), AVX2 (4) and AVX-512 (8), picked at load time by
// the CPU. Same operations lane by lane, and -ffp-contract=off keeps multiply-adds unfused in
// all of them, so the bits are the same on every machine. (core/CMakeLists.txt compiles this
// file with -mtune=icelake-server: with generic tuning GCC makes the table reads scalar.)
//
// The angle is split into whole degrees n and a remainder t in [-0.5, 0.5], both exact; then
//   sin(n + t) = sin n + (sin n (cos t - 1) + cos n sin t)
//   cos(n + t) = cos n + (cos n (cos t - 1) - sin n sin t)
// with sin n and cos n from a table of correctly rounded values and the small corrections
// from short series. Largest error against long double 1.12e-16 over 2M random angles (the
// minimax polynomials on [-45, 45] degrees this replaced: 1.78e-16), and about 20 % faster.
KOMA_TARGET_CLONES("arch=x86-64-v4", "avx2", "default")
void SinCosDegrees(const double* degrees, int n, double* sin, double* cos) {
  using trig_internal::kSinWholeDegrees;
  // sin(-a) = -sin(a) and cos(-a) = cos(a) take the sign off, and fmod is exact by definition.
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
  // Second pass, branch-free (selects only), so it vectorises.
  for (int i = 0; i < n; ++i) {
    const double magnitude = sin[i];  // [0, 360)
    // Rounded to the nearest whole degree by the 1.5 * 2^52 trick (exact below 2^51; no libm
    // call, so the loop vectorises in every build). The remainder is then exact: both are
    // multiples of magnitude's ulp and it is at most 0.5.
    constexpr double kRoundToWhole = 6755399441055744.0;
    const double whole = (magnitude + kRoundToWhole) - kRoundToWhole;  // 0 .. 360
    const double x = (magnitude - whole) * kRadiansPerDegree;
    const double sin_x = SinSmall(x);
    const double cos_x_minus_one = CosSmallMinusOne(x);
    const int index = static_cast<int>(whole);
    const double sin_n = kSinWholeDegrees[index];
    const double cos_n = kSinWholeDegrees[index + 90];
    const double s = sin_n + (sin_n * cos_x_minus_one + cos_n * sin_x);
    const double c = cos_n + (cos_n * cos_x_minus_one - sin_n * sin_x);
    // "+ 0.0" turns a -0 into +0 (and leaves every other value alone).
    const double minus_s = -s;
    sin[i] = (degrees[i] < 0.0 ? minus_s : s) + 0.0;
    cos[i] = c + 0.0;
  }
}

}  // namespace koma

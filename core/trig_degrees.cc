#include "core/trig_degrees.h"

#include <cmath>
#include <utility>

namespace koma {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

// Taylor series for |x| <= pi/4 radians in Horner form. The first omitted terms, x^19/19! and
// x^20/20!, are below 1e-19 there, far under half an ulp of the results.
double SinSeries(double x) {
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

double CosSeries(double x) {
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
  // Reduce in degrees, where every step is exact: sin(-a) = -sin(a) and cos(-a) = cos(a)
  // take the sign off, fmod is exact by definition, and subtracting a multiple of 90 from a
  // value at most twice it is exact (Sterbenz). (Adding 360 to a negative angle would not be.)
  const bool negative = degrees < 0.0;
  const double r = std::fmod(std::fabs(degrees), 360.0);  // [0, 360)
  int quadrant = static_cast<int>(r / 90.0);
  double within = r - 90.0 * quadrant;
  if (within < 0.0) {  // r / 90 rounded up across a quadrant boundary
    --quadrant;
    within += 90.0;
  }
  quadrant %= 4;
  // Past 45 degrees use the complement, so the series only sees |x| <= pi/4.
  const bool complement = within > 45.0;
  const double x = (complement ? 90.0 - within : within) * kRadiansPerDegree;
  double s = SinSeries(x);
  double c = CosSeries(x);
  if (complement) std::swap(s, c);
  // Rotate by the quadrant, put the sign back; "+ 0.0" turns a -0 into +0.
  SinCos result;
  switch (quadrant) {
    case 0: result = {s, c}; break;
    case 1: result = {c, -s}; break;
    case 2: result = {-s, -c}; break;
    default: result = {-c, s}; break;
  }
  if (negative) result.sin = -result.sin;
  result.sin += 0.0;
  result.cos += 0.0;
  return result;
}

}  // namespace koma

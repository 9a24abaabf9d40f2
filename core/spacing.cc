// Holds and tame/tsume spacing of one segment between key poses (docs/semantics.md,
// "RetimeCurves").
#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include "core/koma_uchi.h"

namespace koma {
namespace {

// r^0 .. r^count by repeated multiplication: std::pow's last bit differs between libm
// versions, and the service must give the same bytes on every machine.
std::vector<double> Powers(double r, int count) {
  std::vector<double> powers(static_cast<size_t>(count) + 1);
  powers[0] = 1.0;
  for (int k = 1; k <= count; ++k) powers[k] = powers[k - 1] * r;
  return powers;
}

// One half's geometric fraction F(k) = (s^k - 1) / (s^h - 1), h = drawings / 2 (real), for
// k = 0 .. floor(h), s > 1. Computed with r = 1 / s as r^(h - k) * (1 - r^k) / (1 - r^h), the
// same number rearranged so that no power exceeds 1: s^h overflows a double for long segments
// (s = 4 beyond 1,024 drawings), while r^h only underflows towards 0, losing nothing a double
// could hold.
std::vector<double> HalfFractions(int drawings, double strength) {
  const int half = drawings / 2;       // floor(h)
  const bool odd = drawings % 2 != 0;  // h = half + 1/2: one factor sqrt(r) more
  const double r = 1.0 / strength;
  const double root = odd ? std::sqrt(r) : 1.0;  // sqrt is correctly rounded (IEEE 754)
  const std::vector<double> powers = Powers(r, half);
  const double denominator = 1.0 - powers[half] * root;  // 1 - r^h > 0
  std::vector<double> fractions(static_cast<size_t>(half) + 1);
  for (int k = 0; k <= half; ++k) {
    fractions[k] = powers[half - k] * root * (1.0 - powers[k]) / denominator;
  }
  return fractions;
}

}  // namespace

std::vector<int> HoldLengths(int length, int frames_per_drawing) {
  assert(frames_per_drawing >= 1);
  if (length <= 0) return {};
  // D = ceil(length / n), written so that a huge n cannot overflow.
  const int drawings = length / frames_per_drawing + (length % frames_per_drawing != 0 ? 1 : 0);
  const int base = length / drawings;    // <= n, since length <= D * n
  const int longer = length % drawings;  // that many holds of base + 1 (<= n), first
  std::vector<int> holds(static_cast<size_t>(drawings), base);
  for (int j = 0; j < longer; ++j) ++holds[j];
  return holds;
}

std::vector<int> PoseHoldLengths(int length, int frames_per_drawing) {
  assert(frames_per_drawing >= 1);
  if (length <= 0) return {};
  const int drawings = std::max(1, length / frames_per_drawing);  // D = max(1, floor(L / n))
  const int base = length / drawings;    // >= n when length >= n
  const int longer = length % drawings;  // that many holds of base + 1, first
  std::vector<int> holds(static_cast<size_t>(drawings), base);
  for (int j = 0; j < longer; ++j) ++holds[j];
  return holds;
}

std::vector<double> Spacing(int drawings, double tame, double tsume) {
  if (drawings <= 0) return {};
  if (drawings == 1) return {0.0};  // the key alone
  std::vector<double> spacing(static_cast<size_t>(drawings));
  const double d = static_cast<double>(drawings);
  // First half, j <= D / 2: E_j = F_a(j) / 2 (j / D exactly when s_a = 1, the limit).
  const int half = drawings / 2;
  const std::vector<double> tame_fractions =
      tame == 1.0 ? std::vector<double>() : HalfFractions(drawings, tame);
  for (int j = 0; j <= half; ++j) {  // half < drawings, as drawings >= 2
    spacing[j] = tame == 1.0 ? j / d : 0.5 * tame_fractions[j];
  }
  // Second half, j > D / 2: E_j = 1 - F_b(D - j) / 2, mirrored (j / D when s_b = 1).
  const std::vector<double> tsume_fractions =
      tsume == 1.0 ? std::vector<double>() : HalfFractions(drawings, tsume);
  for (int j = half + 1; j < drawings; ++j) {
    spacing[j] = tsume == 1.0 ? j / d : 1.0 - 0.5 * tsume_fractions[drawings - j];
  }
  return spacing;
}

}  // namespace koma

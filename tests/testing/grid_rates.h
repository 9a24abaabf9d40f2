// The source rates the film-grid property tests run on (tests/core/curves_grid_property_test.cc,
// tests/server/lip_blink_grid_property_test.cc), each with the grid's exact ratio of rates, and
// the reference mappings between source and grid frames written from docs/semantics.md ("The
// film grid"). One table, so that a rate added or a ratio corrected reaches both tests.
#ifndef KOMA_TESTS_TESTING_GRID_RATES_H_
#define KOMA_TESTS_TESTING_GRID_RATES_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace koma::testing {

// A source rate num / den frames per second on a grid of t frames per second, and the grid's
// ratio p / q source frames per grid frame (within 1e-4 of num / (t den); core/film_grid.h).
struct GridRate {
  int64_t num;
  int64_t den;
  int64_t p;
  int64_t q;
  int64_t t = 24;  // the grid, timing_fps (24: what a request that leaves it unset gets)
  double fps() const { return static_cast<double>(num) / static_cast<double>(den); }
  double ratio() const { return static_cast<double>(p) / static_cast<double>(q); }
  // |(p / q) / (R / t) - 1|: 0 for the integer rates.
  double ratio_error() const {
    return std::fabs(static_cast<double>(p * t * den - q * num)) / static_cast<double>(q * num);
  }
  // Grid frame (or fractional time) g in source frames, as the grid computes it.
  double SourceTime(double g) const { return g * static_cast<double>(p) / static_cast<double>(q); }
  friend void PrintTo(const GridRate& r, std::ostream* os) {
    *os << r.num << "/" << r.den << " fps on " << r.t;
  }
};

// 25 .. 240 fps and 29.97 on 24; sources slower than the grid (12, 15, 23.976 fps), where a
// drawing may fall between two source frames and show in none; other grids: 60 on 30, 50 and
// 30 on 12, 24 on 8.
inline std::vector<GridRate> GridRates() {
  return {{25, 1, 25, 24},    {30, 1, 5, 4},     {50, 1, 25, 12},           {60, 1, 5, 2},
          {100, 1, 25, 6},    {120, 1, 5, 1},    {240, 1, 10, 1},           {2997, 100, 246, 197},
          {12, 1, 1, 2},      {15, 1, 5, 8},     {24000, 1001, 1000, 1001}, {60, 1, 2, 1, 30},
          {50, 1, 25, 6, 12}, {30, 1, 5, 2, 12}, {24, 1, 3, 1, 8}};
}

// The gtest name of a rate: Fps30, Fps2997_100, Fps60_On30.
struct GridRateName {
  template <typename ParamInfo>
  std::string operator()(const ParamInfo& info) const {
    const GridRate& r = info.param;
    return "Fps" + std::to_string(r.num) + (r.den == 1 ? "" : "_" + std::to_string(r.den)) +
           (r.t == 24 ? "" : "_On" + std::to_string(r.t));
  }
};

// The grid frame nearest source frame k (k * q / p grid frames), ties to the earlier.
inline int NearestGridFrame(const GridRate& r, int64_t k) {
  const int64_t g = (k * r.q) / r.p;
  const int64_t twice_past = 2 * (k * r.q - g * r.p);  // 2 (x - g), times p
  return static_cast<int>(twice_past > r.p ? g + 1 : g);
}

// The grid frames source frame k may show: floor(k * t / R), and its neighbour when
// k * t / R lies within the ratio's error of the boundary between them; within [0, last].
inline std::vector<int> GridFramesOf(const GridRate& r, int64_t k, int last) {
  const int64_t num = k * r.t * r.den;
  const int64_t g = num / r.num;
  const double frac = static_cast<double>(num - g * r.num) / static_cast<double>(r.num);
  const double tol = r.ratio_error() * static_cast<double>(num) / static_cast<double>(r.num);
  std::vector<int> out;
  if (frac < tol && g >= 1) out.push_back(static_cast<int>(g - 1));
  out.push_back(static_cast<int>(g));
  if (1.0 - frac < tol) out.push_back(static_cast<int>(g + 1));
  for (int& f : out) f = std::min(f, last);
  return out;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_GRID_RATES_H_

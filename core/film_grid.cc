#include "core/film_grid.h"

#include <climits>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace koma {
namespace {

// Largest denominator of the rate ratio: fine enough for any real pair of rates (29.97 / 24 is
// 246 / 197 within 1e-4), small enough that p * index stays far inside int64 for any clip the
// server accepts (indices below 2^31).
constexpr int64_t kMaxDenominator = 100000;
// Largest denominator when the source is more than kMaxDenominator times slower than the grid:
// 1e9 grid frames per source frame, still far from overflow in k * q for any k below 2^31.
constexpr int64_t kMaxUpsampling = 1000000000;
// Largest numerator: a grid frame 2^30 source frames long already holds any clip the server
// accepts in one grid frame; capping the ratio there keeps it an int64 (a timing_fps of 1e-300
// gives a ratio near 1e306) and 2 * g * p far from overflow for any g below 2^31.
constexpr int64_t kMaxNumerator = int64_t{1} << 30;

// floor(a / b) for b > 0 and any a.
int64_t FloorDiv(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// ceil(a / b) for b > 0 and any a.
int64_t CeilDiv(int64_t a, int64_t b) { return -FloorDiv(-a, b); }

// int of an int64 that is >= 0, saturating at INT_MAX.
int SaturateToInt(int64_t value) { return value > INT_MAX ? INT_MAX : static_cast<int>(value); }

// The first continued-fraction convergent p / q of `ratio` (> 0) within kSameRateTolerance of
// it, relative: the closest fraction with so small a denominator (not always the one with the
// smallest denominator within the tolerance: 29.97 / 24 gives 246 / 197, 1.5e-5 off, where
// 231 / 185 is 8e-5 off). Ratios from kMaxNumerator up give kMaxNumerator / 1.
void SimplestFraction(double ratio, int64_t* p, int64_t* q) {
  if (ratio >= static_cast<double>(kMaxNumerator)) {
    *p = kMaxNumerator;
    *q = 1;
    return;
  }
  int64_t p0 = 1, q0 = 0;  // convergent k - 1
  int64_t p1 = static_cast<int64_t>(std::floor(ratio)), q1 = 1;
  double rest = ratio - std::floor(ratio);
  while (std::fabs(static_cast<double>(p1) / static_cast<double>(q1) - ratio) >
             kSameRateTolerance * ratio &&
         rest > 0) {
    const double inverse = 1.0 / rest;
    if (std::floor(inverse) * static_cast<double>(q1) > static_cast<double>(kMaxDenominator)) break;
    const int64_t a = static_cast<int64_t>(std::floor(inverse));
    const int64_t p2 = a * p1 + p0, q2 = a * q1 + q0;
    if (q2 > kMaxDenominator) break;
    p0 = p1, q0 = q1, p1 = p2, q1 = q2;
    rest = inverse - std::floor(inverse);
  }
  if (p1 == 0) {
    // A ratio below 1 / kMaxDenominator (1 fps counted at 1000 fps is 1e-3; 0.001 fps at 1000
    // is 1e-6): 1 / round(1 / ratio) is within 5e-6 of it. Capped at kMaxUpsampling.
    p1 = 1;
    q1 = 1.0 / ratio >= static_cast<double>(kMaxUpsampling) ? kMaxUpsampling
                                                            : std::llround(1.0 / ratio);
  }
  *p = p1;
  *q = q1;
}

}  // namespace

absl::Status ValidateTimingFps(double timing_fps, absl::string_view field) {
  if (!std::isfinite(timing_fps) || timing_fps > kMaxTimingFps) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", timing_fps, " must be finite and <= ", kMaxTimingFps,
                     " frames per second (unset = 24, <= 0 = count in source frames)"));
  }
  return absl::OkStatus();
}

absl::Status ValidateSourceFps(double source_fps, absl::string_view field) {
  if (!(source_fps >= kMinSourceFps && source_fps <= kMaxSourceFps)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": a rate of ", source_fps, " frames per second is outside ",
                     kMinSourceFps, " .. ", kMaxSourceFps,
                     ", the rates a film grid can count (timing_fps: 0 counts in "
                     "source frames)"));
  }
  return absl::OkStatus();
}

std::optional<FilmGrid> FilmGrid::Make(double source_fps, double timing_fps) {
  if (!(timing_fps > 0) || !(source_fps >= kMinSourceFps && source_fps <= kMaxSourceFps)) {
    return std::nullopt;
  }
  if (std::fabs(source_fps - timing_fps) <= kSameRateTolerance * timing_fps) return std::nullopt;
  int64_t p = 1, q = 1;
  SimplestFraction(source_fps / timing_fps, &p, &q);
  return FilmGrid(source_fps, timing_fps, p, q);
}

int FilmGrid::GridFrameCount(int source_frames) const {
  if (source_frames < 1) return 0;
  const int last = GridFrameOf(source_frames - 1);
  return last == INT_MAX ? INT_MAX : last + 1;
}

int FilmGrid::NearestSourceFrame(int g, int last) const {
  // ceil(g p / q - 1/2) = ceil((2 g p - q) / 2q): an exact half goes down.
  const int64_t k = CeilDiv(2 * static_cast<int64_t>(g) * p_ - q_, 2 * q_);
  return static_cast<int>(k > last ? last : (k < 0 ? 0 : k));
}

int FilmGrid::GridFrameOf(int k) const {
  return SaturateToInt(FloorDiv(static_cast<int64_t>(k) * q_, p_));
}

int FilmGrid::NearestGridFrame(double source_frame) const {
  const double g = source_frame * static_cast<double>(q_) / static_cast<double>(p_);
  const double nearest = std::ceil(g - 0.5);
  if (!(nearest > 0)) return 0;  // NaN too
  return nearest >= static_cast<double>(INT_MAX) ? INT_MAX : static_cast<int>(nearest);
}

double FilmGrid::SourceTime(double g) const {
  return g * static_cast<double>(p_) / static_cast<double>(q_);
}

int FilmGrid::FirstSourceFrameAtOrAfter(int g) const {
  return SaturateToInt(CeilDiv(static_cast<int64_t>(g) * p_, q_));
}

}  // namespace koma

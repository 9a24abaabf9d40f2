// FilmGrid (core/film_grid.h): the exact mapping between source frames and 24 fps grid frames,
// checked against integer arithmetic on the true rates, and the same-rate detection that keeps
// 24 fps input (whatever BVH rounding its Frame Time has) off the grid.
#include "core/film_grid.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

FilmGrid GridOf(double source_fps, double timing_fps = 24.0) {
  const std::optional<FilmGrid> grid = FilmGrid::Make(source_fps, timing_fps);
  EXPECT_TRUE(grid.has_value()) << source_fps << " fps on a " << timing_fps << " fps grid";
  return grid.value_or(*FilmGrid::Make(48.0, 24.0));
}

// A rate as the exact fraction num / den frames per second.
struct Rate {
  int64_t num;
  int64_t den;
};

// The reference, written from docs/semantics.md, "The film grid" with the true rates, a source at
// `r` on a 24 fps grid. Grid frame g lies at g / 24 s, source frame k at k * den / num s.
int RefGridFrameOf(Rate r, int64_t k) { return static_cast<int>((k * 24 * r.den) / r.num); }
int RefGridFrameCount(Rate r, int64_t n) {
  int count = 0;  // grid frames at or before the last source frame's time
  while (static_cast<int64_t>(count) * r.num <= (n - 1) * 24 * r.den) ++count;
  return count;
}
int RefNearestSourceFrame(Rate r, int64_t g) {
  // |k / source - g / 24| in units of 1 / (24 num) s: |24 k den - g num|; ties to the earlier.
  int64_t best = 0;
  for (int64_t k = 1; k * 24 * r.den <= g * r.num + 24 * r.den; ++k) {
    if (std::llabs(24 * k * r.den - g * r.num) < std::llabs(24 * best * r.den - g * r.num)) {
      best = k;
    }
  }
  return static_cast<int>(best);
}
int RefFirstSourceFrameAtOrAfter(Rate r, int64_t g) {
  int64_t k = 0;
  while (24 * k * r.den < g * r.num) ++k;
  return static_cast<int>(k);
}

// Every mapping of `grid` against the reference for `r`, on the first `frames` source frames.
void ExpectMapsLike(const FilmGrid& grid, Rate r, int frames) {
  for (int k = 0; k < frames; ++k) {
    ASSERT_EQ(grid.GridFrameOf(k), RefGridFrameOf(r, k)) << "source frame " << k;
    ASSERT_EQ(grid.GridFrameCount(k + 1), RefGridFrameCount(r, k + 1)) << k + 1 << " frames";
  }
  const int grid_frames = grid.GridFrameCount(frames);
  for (int g = 0; g < grid_frames; ++g) {
    ASSERT_EQ(grid.NearestSourceFrame(g, frames - 1), RefNearestSourceFrame(r, g))
        << "grid frame " << g;
    ASSERT_EQ(grid.FirstSourceFrameAtOrAfter(g), RefFirstSourceFrameAtOrAfter(r, g))
        << "grid frame " << g;
  }
}

TEST(FilmGridTest, SixtyFpsTiesGoToTheEarlierFrame) {
  const FilmGrid grid = GridOf(60.0);
  // 2.5 source frames per grid frame: grid frame 1 lies at source time 2.5, between 2 and 3.
  EXPECT_EQ(grid.NearestSourceFrame(0, 100), 0);
  EXPECT_EQ(grid.NearestSourceFrame(1, 100), 2);
  EXPECT_EQ(grid.NearestSourceFrame(2, 100), 5);
  EXPECT_EQ(grid.NearestSourceFrame(3, 100), 7);
  EXPECT_EQ(grid.NearestSourceFrame(4, 100), 10);
  EXPECT_EQ(grid.NearestSourceFrame(5, 100), 12);
  EXPECT_EQ(grid.NearestSourceFrame(5, 11), 11) << "clamped to the last frame";
  // Source frame k falls in grid frame floor(k / 2.5).
  for (int k : {0, 1, 2}) EXPECT_EQ(grid.GridFrameOf(k), 0) << k;
  for (int k : {3, 4}) EXPECT_EQ(grid.GridFrameOf(k), 1) << k;
  EXPECT_EQ(grid.GridFrameOf(5), 2);
  EXPECT_EQ(grid.GridFrameOf(7), 2);
  EXPECT_EQ(grid.GridFrameOf(8), 3);
  EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(0), 0);
  EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(1), 3);
  EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(2), 5);
  EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(3), 8);
  EXPECT_DOUBLE_EQ(grid.SourceTime(3), 7.5);
  EXPECT_EQ(grid.NearestGridFrame(1.25), 0) << "a tie goes to the earlier grid frame";
  EXPECT_EQ(grid.NearestGridFrame(1.26), 1);
  ExpectMapsLike(grid, {60, 1}, 1000);
}

TEST(FilmGridTest, GridFrameCountCountsGridFramesAtOrBeforeTheLastSourceFrame) {
  const FilmGrid grid = GridOf(60.0);
  EXPECT_EQ(grid.GridFrameCount(0), 0);
  EXPECT_EQ(grid.GridFrameCount(1), 1);
  EXPECT_EQ(grid.GridFrameCount(3), 1);    // last frame at 2/60 s < 1/24 s
  EXPECT_EQ(grid.GridFrameCount(4), 2);    // last frame at 3/60 s >= 1/24 s
  EXPECT_EQ(grid.GridFrameCount(6), 3);    // 5/60 s is exactly grid frame 2
  EXPECT_EQ(grid.GridFrameCount(61), 25);  // one second: grid frames 0 .. 24
  EXPECT_EQ(GridOf(120.0).GridFrameCount(61), 13);
  EXPECT_EQ(GridOf(30.0).GridFrameCount(75), 60);
}

TEST(FilmGridTest, RoundedFrameTimesOfSixtyFpsMapExactlyLikeSixty) {
  const FilmGrid exact = GridOf(60.0);
  for (double frame_time : {0.0166667, 0.016666, 0.01666667}) {
    SCOPED_TRACE(frame_time);
    const FilmGrid grid = GridOf(1.0 / frame_time);
    ExpectMapsLike(grid, {60, 1}, 2000);
    for (int g = 0; g < 800; ++g) {
      ASSERT_EQ(grid.NearestSourceFrame(g, 1999), exact.NearestSourceFrame(g, 1999)) << g;
    }
  }
}

TEST(FilmGridTest, IntegerRatesMapExactly) {
  for (Rate r : {Rate{25, 1}, Rate{30, 1}, Rate{50, 1}, Rate{100, 1}, Rate{120, 1}, Rate{240, 1},
                 Rate{48, 1}, Rate{23, 1}}) {
    SCOPED_TRACE(r.num);
    ExpectMapsLike(GridOf(static_cast<double>(r.num)), r, 1200);
  }
}

TEST(FilmGridTest, NtscRateMapsLikeTheTrueRateForMinutes) {
  // 29.97 / 24 becomes 246 / 197 (1.5e-5 off): the mapping equals the true rate's until the
  // error reaches a tie, grid frame 199 (6.6 s) here; on the first 190 grid frames it must.
  ExpectMapsLike(GridOf(29.97), {2997, 100}, 240);
  const FilmGrid grid = GridOf(29.97);
  EXPECT_EQ(grid.GridFrameCount(30), 24);  // 29 / 29.97 s holds grid frames 0 .. 23
  // Over a minute the drift stays below a grid frame.
  const int minute = 60 * 2997 / 100;
  EXPECT_NEAR(grid.GridFrameOf(minute), RefGridFrameOf({2997, 100}, minute), 1);
}

TEST(FilmGridTest, UpsamplingTwelveFpsShowsEachSourceFrameOnTwoGridFrames) {
  const FilmGrid grid = GridOf(12.0);
  EXPECT_EQ(grid.GridFrameCount(5), 9);  // 4 / 12 s = 8 / 24 s
  // Grid frame 2k is source frame k; 2k + 1 lies half way: the tie goes to k.
  for (int g = 0; g < 9; ++g) EXPECT_EQ(grid.NearestSourceFrame(g, 4), g / 2) << g;
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(grid.GridFrameOf(k), 2 * k) << k;
    EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(2 * k), k);
    EXPECT_EQ(grid.FirstSourceFrameAtOrAfter(2 * k + 1), k + 1);
  }
  ExpectMapsLike(grid, {12, 1}, 500);
  ExpectMapsLike(GridOf(10.0), {10, 1}, 500);
}

TEST(FilmGridTest, TwentyFourFpsAndItsRoundedFrameTimesCountInSourceFrames) {
  for (double frame_time : {1.0 / 24.0, 0.041667, 0.0416667, 0.04166667, 0.0416666}) {
    EXPECT_FALSE(FilmGrid::Make(1.0 / frame_time, 24.0).has_value()) << frame_time;
  }
  EXPECT_FALSE(FilmGrid::Make(30.0, 30.0003).has_value()) << "same rate, another grid";
  // Just outside the 1e-4 tolerance: a grid.
  EXPECT_TRUE(FilmGrid::Make(24.0 * (1 + 2e-4), 24.0).has_value());
  EXPECT_TRUE(FilmGrid::Make(1.0 / 0.0417, 24.0).has_value());
  EXPECT_TRUE(FilmGrid::Make(23.0, 24.0).has_value());
}

TEST(FilmGridTest, ZeroOrNegativeTimingFpsOrAnImpossibleSourceRateMeansNoGrid) {
  EXPECT_FALSE(FilmGrid::Make(60.0, 0.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(60.0, -5.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(60.0, std::nan("")).has_value());
  EXPECT_FALSE(FilmGrid::Make(0.0, 24.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(std::nan(""), 24.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(std::numeric_limits<double>::infinity(), 24.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(2e6, 24.0).has_value());
  EXPECT_FALSE(FilmGrid::Make(-60.0, 24.0).has_value());
}

TEST(FilmGridTest, ExtremeRatiosStayInRange) {
  // A grid frame far longer than any clip: every clip spans one grid frame.
  const FilmGrid coarse = GridOf(1e6, 1e-300);
  EXPECT_EQ(coarse.GridFrameCount(2), 1);
  EXPECT_EQ(coarse.GridFrameCount(1 << 30), 1);  // 2^30 source frames per grid frame
  EXPECT_EQ(coarse.NearestSourceFrame(0, 10), 0);
  EXPECT_EQ(GridOf(30.0, 1e-9).GridFrameCount(1000000), 1);
  // A frame every 1000 s on a 24 fps grid: 24000 grid frames a source frame; a count past
  // INT_MAX saturates rather than wrapping (the server then refuses it by --max_values).
  const FilmGrid fine = GridOf(1e-3, 24.0);
  EXPECT_EQ(fine.GridFrameOf(1), 24000);
  EXPECT_EQ(fine.GridFrameCount(2), 24001);
  EXPECT_EQ(fine.GridFrameCount(100000), INT_MAX);
  EXPECT_EQ(fine.GridFrameOf(100000), INT_MAX);
  EXPECT_GE(fine.GridFrameCount(INT_MAX), 1);
  // More than 1e5 grid frames a source frame (beyond the continued fraction's denominator
  // bound): still the true ratio, not a rate clipped to 1e5. A frame every 1000 s at 1000 fps
  // is 1e6 grid frames a source frame, one every 200 s 200000.
  EXPECT_EQ(GridOf(1e-3, 1000.0).GridFrameOf(1), 1000000);
  EXPECT_EQ(GridOf(1e-3, 1000.0).GridFrameCount(3), 2000001);
  EXPECT_EQ(GridOf(5e-3, 1000.0).GridFrameOf(1), 200000);
  EXPECT_EQ(GridOf(5e-3, 1000.0).FirstSourceFrameAtOrAfter(200001), 2);
  EXPECT_EQ(GridOf(5e-3, 1000.0).NearestSourceFrame(300000, 9), 1);  // a tie: the earlier
  EXPECT_EQ(GridOf(1e-3, 1e300).GridFrameOf(1), 1000000000);        // capped at 1e9
}

TEST(FilmGridTest, ValidateTimingFps) {
  for (double ok : {24.0, 0.0, -5.0, 1000.0, 12.5, 1e-9}) {
    EXPECT_THAT(ValidateTimingFps(ok, "timing_fps"), IsOk()) << ok;
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (auto [bad, shown] :
       {std::pair{std::nan(""), "nan"}, std::pair{inf, "inf"}, std::pair{-inf, "-inf"},
        std::pair{1001.0, "1001"}, std::pair{1e300, "1e+300"}}) {
    EXPECT_THAT(
        ValidateTimingFps(bad, "timing_fps"),
        StatusIs(absl::StatusCode::kInvalidArgument,
                 HasSubstr(std::string("timing_fps: ") + shown + " must be finite and <= 1000")))
        << shown;
  }
}

TEST(FilmGridTest, ValidateSourceFps) {
  EXPECT_THAT(ValidateSourceFps(120.0, "motion.frame_time"), IsOk());
  EXPECT_THAT(ValidateSourceFps(1e-3, "motion.frame_time"), IsOk());
  for (double bad : {0.0, -30.0, std::nan(""), std::numeric_limits<double>::infinity(), 2e6}) {
    EXPECT_THAT(ValidateSourceFps(bad, "motion.frame_time"),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("motion.frame_time")))
        << bad;
  }
}

}  // namespace
}  // namespace koma

// A given RetimeSkeletal timing (core/given_skeletal_timing.h): hand-worked expansions on and off
// the film grid, and the validation messages.
#include "core/given_skeletal_timing.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr FrameKind O = FrameKind::kOriginal;
constexpr FrameKind H = FrameKind::kHeld;

TEST(GivenSkeletalTimingTest, WithoutAGridEachEntryIsAnOutputFrame) {
  // 6 source frames; the timing swaps two drawings, holds one and repeats frame 1 later.
  const GivenSkeletalRetimed r = ApplyGivenSkeletalTiming({0, 3, 3, 1, 1, 1}, std::nullopt, 6,
                                                          /*at_source_rate=*/true);
  EXPECT_THAT(r.map.source_frames, ElementsAre(0, 3, 3, 1, 1, 1));
  EXPECT_THAT(r.map.kinds, ElementsAre(O, O, H, O, H, H));
  EXPECT_THAT(r.map.deleted, ElementsAre(2, 4, 5));
  EXPECT_TRUE(r.map.hidden.empty());
  EXPECT_TRUE(r.grid_frames.empty());
  EXPECT_TRUE(r.grid_samples.empty());
  EXPECT_EQ(r.longest_hold, 3);
  EXPECT_EQ(r.map.omissions_applied + r.map.holds_applied + r.map.duplicates_applied, 0);
}

TEST(GivenSkeletalTimingTest, OnTheGridAtTheSourceRateEachGridFrameCoversItsSourceFrames) {
  // 40 frames at 120 fps on the 24 fps grid: 5 source frames a grid frame, grid frames 0..7
  // sample 0, 5, ..., 35. Given 4 grid frames: the output is the 20 source frames before grid
  // frame 4's time, each showing its grid frame's entry.
  const std::optional<FilmGrid> grid = FilmGrid::Make(120.0, 24.0);
  ASSERT_TRUE(grid.has_value());
  const GivenSkeletalRetimed r = ApplyGivenSkeletalTiming({0, 7, 7, 15}, grid, 40, true);
  ASSERT_EQ(r.map.source_frames.size(), 20u);
  for (int k = 0; k < 20; ++k) {
    const int t = k / 5;
    EXPECT_EQ(r.grid_frames[k], t) << k;
    EXPECT_EQ(r.map.source_frames[k], (std::vector<int>{0, 7, 7, 15})[t]) << k;
    EXPECT_EQ(r.map.kinds[k], t == 2 ? H : O) << k;
  }
  EXPECT_THAT(r.grid_samples, ElementsAre(0, 5, 10, 15, 20, 25, 30, 35));
  // Samples the timing shows nowhere (7 is no sample: it is shown, and not listed).
  EXPECT_THAT(r.map.deleted, ElementsAre(5, 10, 20, 25, 30, 35));
  EXPECT_EQ(r.longest_hold, 2);
}

TEST(GivenSkeletalTimingTest, OnTheGridAtTheTimingRateEachEntryIsAnOutputFrame) {
  const std::optional<FilmGrid> grid = FilmGrid::Make(120.0, 24.0);
  const GivenSkeletalRetimed r = ApplyGivenSkeletalTiming({35, 0, 0}, grid, 40, false);
  EXPECT_THAT(r.map.source_frames, ElementsAre(35, 0, 0));
  EXPECT_THAT(r.map.kinds, ElementsAre(O, O, H));
  EXPECT_THAT(r.grid_frames, ElementsAre(0, 1, 2));
}

TEST(GivenSkeletalTimingTest, ASourceSlowerThanTheGridShowsEveryOtherGridFrame) {
  // 12 fps on the 24 fps grid: source frame k is grid frame 2k; grid frames 1, 3 show nowhere.
  const std::optional<FilmGrid> grid = FilmGrid::Make(12.0, 24.0);
  // 3 frames span grid frames 0..4.
  const GivenSkeletalRetimed r = ApplyGivenSkeletalTiming({0, 1, 2, 1, 0}, grid, 3, true);
  EXPECT_THAT(r.grid_frames, ElementsAre(0, 2, 4));
  EXPECT_THAT(r.map.source_frames, ElementsAre(0, 2, 0));
  EXPECT_THAT(r.grid_samples, ElementsAre(0, 0, 1, 1, 2));
}

TEST(GivenSkeletalTimingTest, ValidationNamesTheFieldAndTheValue) {
  const char* f = "given_timing.source_frames";
  EXPECT_THAT(ValidateGivenSkeletalTiming({0, 799, 2}, 800, 800, f), IsOk());
  EXPECT_THAT(ValidateGivenSkeletalTiming({}, 800, 800, f),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("given_timing.source_frames: empty")));
  EXPECT_THAT(ValidateGivenSkeletalTiming({0, 812}, 800, 800, f),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("given_timing.source_frames[1]: 812 is past the clip's last "
                                 "frame 799")));
  EXPECT_THAT(ValidateGivenSkeletalTiming({0, -1}, 800, 800, f),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("given_timing.source_frames[1]: -1 must be >= 0")));
  EXPECT_THAT(ValidateGivenSkeletalTiming({0, 0, 0}, 10, 2, f),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("3 frames is longer than the clip's 2 grid frames")));
  EXPECT_THAT(ValidateGivenSkeletalTiming({0, 0, 0}, 2, 2, f),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("3 frames is longer than the clip's 2 frames")));
}

}  // namespace
}  // namespace koma

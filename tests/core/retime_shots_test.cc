// Cuts, shares by length, the drawing target of step B and shot-by-shot retiming
// (docs/semantics.md, "Cuts and shots", "Omission rate", "Drawing rate").
#include "core/retime_shots.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/distance.h"
#include "core/film_grid.h"
#include "core/retime.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::IsEmpty;

// ssd[0] = 0 and the pairs given.
std::vector<double> Ssd(std::vector<double> pairs) {
  pairs.insert(pairs.begin(), 0.0);
  return pairs;
}

TEST(FindCutsTest, CalibrationFrameAtTheStart) {
  // A T-pose pair 70x its only neighbour and far above the median.
  EXPECT_THAT(FindCuts(Ssd({915, 13, 18, 20, 17, 19, 18, 16}), CutRule{}), ElementsAre(1));
}

TEST(FindCutsTest, CalibrationFrameAtTheEnd) {
  EXPECT_THAT(FindCuts(Ssd({18, 20, 17, 19, 18, 16, 900}), CutRule{}), ElementsAre(7));
}

TEST(FindCutsTest, JoinOfTwoTakes) {
  EXPECT_THAT(FindCuts(Ssd({18, 20, 17, 2000, 19, 18, 16}), CutRule{}), ElementsAre(4));
}

TEST(FindCutsTest, GlitchFrameIsTwoCuts) {
  // Into the glitch and out of it: a run of two jumps, each far above the pairs around it.
  EXPECT_THAT(FindCuts(Ssd({18, 20, 17, 1500, 1400, 19, 18, 16}), CutRule{}), ElementsAre(4, 5));
}

TEST(FindCutsTest, FastMotionThatRisesAndFallsIsNotACut) {
  // The pitch's throw: 75x the median, but 1.05x its faster neighbour.
  EXPECT_THAT(FindCuts(Ssd({10, 12, 11, 60, 300, 1300, 1365, 700, 200, 40, 12, 10, 11}),
                       CutRule{}),
              IsEmpty());
}

TEST(FindCutsTest, ThreeJumpsInARowAreMotionNotACut) {
  EXPECT_THAT(FindCuts(Ssd({10, 12, 11, 3000, 3100, 2900, 12, 10, 11}), CutRule{}), IsEmpty());
}

TEST(FindCutsTest, BothGatesAreNeeded) {
  // 30x its neighbours but only 6x the median (a lively clip): not a jump.
  EXPECT_THAT(FindCuts(Ssd({5, 100, 100, 100, 5, 150, 5, 100, 100}), CutRule{}), IsEmpty());
  // 200x the median but only 13x its neighbours: not isolated.
  EXPECT_THAT(FindCuts(Ssd({10, 10, 10, 150, 2000, 150, 10, 10}), CutRule{}), IsEmpty());
}

TEST(FindCutsTest, ThresholdsAreInclusiveForNeighboursStrictForTheMedian) {
  const CutRule rule{10.0, 10.0};
  // Median 1; 10 is not > 10 x 1.
  EXPECT_THAT(FindCuts(Ssd({1, 1, 10, 1, 1}), rule), IsEmpty());
  // 11 > 10, and 11 >= 10 x 1.1.
  EXPECT_THAT(FindCuts(Ssd({1, 1.1, 11, 1, 1}), rule), ElementsAre(3));
  EXPECT_THAT(FindCuts(Ssd({1, 1.2, 11, 1, 1}), rule), IsEmpty());
}

TEST(FindCutsTest, StillClipWithOneJump) {
  // The median is 0: every moving pair is a jump; one isolated against still neighbours.
  EXPECT_THAT(FindCuts(Ssd({0, 0, 0, 5, 0, 0}), CutRule{}), ElementsAre(4));
}

TEST(FindCutsTest, OffAndTooShort) {
  EXPECT_THAT(FindCuts(Ssd({915, 13, 18, 20}), CutRule{0.0, 20.0}), IsEmpty());
  EXPECT_THAT(FindCuts(Ssd({915}), CutRule{}), IsEmpty());  // 2 frames: nothing outside
  EXPECT_THAT(FindCuts(Ssd({915, 900}), CutRule{}), IsEmpty());  // the whole clip jumps
}

TEST(FindCutsTest, ValidateNamesTheField) {
  EXPECT_THAT(ValidateCutRule(CutRule{0.5, 20}),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       ::testing::HasSubstr("cut_neighbour_ratio: 0.5")));
  EXPECT_THAT(ValidateCutRule(CutRule{20, -1}),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       ::testing::HasSubstr("cut_median_ratio: -1")));
  EXPECT_THAT(ValidateCutRule(CutRule{0, 0}), IsOk());
  EXPECT_THAT(ValidateCutRule(CutRule{}), IsOk());
}

// The rule as written, pair by pair: for each pair, find its run of jumps by scanning.
std::vector<int32_t> NaiveCuts(const std::vector<double>& ssd, const CutRule& rule) {
  std::vector<int32_t> cuts;
  const int n = static_cast<int>(ssd.size());
  if (rule.neighbour_ratio == 0.0 || n < 3) return cuts;
  std::vector<double> pairs(ssd.begin() + 1, ssd.end());
  std::sort(pairs.begin(), pairs.end());
  const double median = pairs[(pairs.size() - 1) / 2];
  auto jump = [&](int k) { return k >= 1 && k < n && ssd[k] > rule.median_ratio * median; };
  for (int k = 1; k < n; ++k) {
    if (!jump(k)) continue;
    int a = k;
    int b = k;
    while (jump(a - 1)) --a;
    while (jump(b + 1)) ++b;
    if (b - a + 1 > kMaxCutPairs) continue;
    std::vector<double> outside;
    if (a - 1 >= 1) outside.push_back(ssd[a - 1]);
    if (b + 1 < n) outside.push_back(ssd[b + 1]);
    if (outside.empty()) continue;
    const double least = *std::min_element(ssd.begin() + a, ssd.begin() + b + 1);
    if (least >= rule.neighbour_ratio * *std::max_element(outside.begin(), outside.end())) {
      cuts.push_back(k);
    }
  }
  return cuts;
}

TEST(FindCutsTest, AgreesWithTheRuleAsWrittenOnRandomSsd) {
  SplitMix64 rng(28);
  for (int clip = 0; clip < 3000; ++clip) {
    const int n = rng.Int(1, 40);
    std::vector<double> ssd(static_cast<size_t>(n), 0.0);
    for (int k = 1; k < n; ++k) {
      // Mostly small, some zeros, some huge, exact ties.
      const int pick = rng.Int(0, 9);
      ssd[k] = pick == 0 ? 0.0 : pick == 1 ? 1000.0 * rng.Int(1, 3) : rng.Int(1, 20);
    }
    const CutRule rule{rng.OneIn(5) ? 0.0 : static_cast<double>(rng.Int(1, 30)),
                       static_cast<double>(rng.Int(0, 30))};
    ASSERT_EQ(FindCuts(ssd, rule), NaiveCuts(ssd, rule)) << "clip " << clip;
  }
}

TEST(SplitByLengthTest, HandWorked) {
  EXPECT_THAT(SplitByLength(4, {50, 50}), ElementsAre(2, 2));
  EXPECT_THAT(SplitByLength(4, {30, 70}), ElementsAre(1, 3));  // 1.2, 2.8
  EXPECT_THAT(SplitByLength(5, {1, 1}), ElementsAre(3, 2));    // tie: the earlier shot
  EXPECT_THAT(SplitByLength(3, {0, 10, 0}), ElementsAre(0, 3, 0));
  EXPECT_THAT(SplitByLength(0, {5, 5}), ElementsAre(0, 0));
  EXPECT_THAT(SplitByLength(7, {0, 0}), ElementsAre(0, 0));
}

TEST(SplitByLengthTest, SharesAddUpAndStayWithinOneOfTheQuota) {
  SplitMix64 rng(7);
  for (int round = 0; round < 2000; ++round) {
    std::vector<int> lengths(static_cast<size_t>(rng.Int(1, 6)));
    int64_t sum = 0;
    for (int& l : lengths) sum += (l = rng.Int(0, 500));
    const int total = rng.Int(0, 400);
    const std::vector<int> shares = SplitByLength(total, lengths);
    int64_t given = 0;
    for (size_t i = 0; i < lengths.size(); ++i) {
      given += shares[i];
      if (sum == 0) continue;
      const double quota = static_cast<double>(total) * lengths[i] / static_cast<double>(sum);
      EXPECT_LE(std::abs(shares[i] - quota), 1.0);
    }
    EXPECT_EQ(given, sum == 0 ? 0 : total);
  }
}

TEST(ShotOptionsTest, SingleShotKeepsTheTotals) {
  ShotBudget budget;
  budget.totals = DefaultRetimeOptions(105);
  const std::vector<RetimeOptions> options = ShotOptions(budget, {105});
  ASSERT_EQ(options.size(), 1u);
  EXPECT_EQ(options[0].omissions, 4);
  EXPECT_EQ(options[0].holds, 35);
  EXPECT_EQ(options[0].max_drawings, 0);
}

TEST(ShotOptionsTest, SharesByLengthAndShortShotsPassThrough) {
  ShotBudget budget;
  budget.totals = DefaultRetimeOptions(101);  // 4 omissions, 33 holds
  const std::vector<RetimeOptions> options = ShotOptions(budget, {1, 40, 60});
  EXPECT_EQ(options[0].omissions, 0);
  EXPECT_EQ(options[0].holds, 0);
  EXPECT_EQ(options[1].omissions, 2);  // 1.6 -> 1, +1 (remainder .6 beats .4)
  EXPECT_EQ(options[2].omissions, 2);  // 2.4
  EXPECT_EQ(options[1].holds, 13);     // 13.2
  EXPECT_EQ(options[2].holds, 20);     // 19.8 -> 19, +1
}

TEST(ShotOptionsTest, OmissionsNeverReachAShortShotsEnds) {
  ShotBudget budget;
  budget.totals.omissions = 20;
  budget.totals.holds = 0;
  const std::vector<RetimeOptions> options = ShotOptions(budget, {4, 36});
  EXPECT_EQ(options[0].omissions, 1);  // share 2, at most 4 - 3
  EXPECT_EQ(options[1].omissions, 18);
}

TEST(ShotOptionsTest, DrawingRate) {
  ShotBudget budget;
  budget.totals = DefaultRetimeOptions(100);
  budget.drawings_per_frame = 8.0 / 24.0;
  budget.holds_per_frame_cap = true;
  const std::vector<RetimeOptions> options = ShotOptions(budget, {100, 2});
  EXPECT_EQ(options[0].max_drawings, 34);  // ceil(33.3)
  EXPECT_EQ(options[0].holds, 1200);       // 4 x 100 frames x max_hold 3: a bound
  EXPECT_EQ(options[1].holds, 0);          // too short to retime
}

TEST(OmissionsForRateTest, RoundsHalfUpAndStaysInside) {
  EXPECT_EQ(OmissionsForRate(1.0, 960, 24.0), 40);   // 40 s at 1 a second
  EXPECT_EQ(OmissionsForRate(0.5, 105, 24.0), 2);    // 2.19
  EXPECT_EQ(OmissionsForRate(0.5, 108, 24.0), 2);    // 2.25
  EXPECT_EQ(OmissionsForRate(0.5, 132, 24.0), 3);    // 2.75
  EXPECT_EQ(OmissionsForRate(0.25, 48, 24.0), 1);    // 0.5 rounds up
  EXPECT_EQ(OmissionsForRate(100.0, 10, 24.0), 7);   // at most frames - 3
  EXPECT_EQ(OmissionsForRate(0.0, 960, 24.0), 0);
  EXPECT_EQ(OmissionsForRate(1.0, 2, 24.0), 0);
}

// Random clips for the drawing target: continuous, with still stretches.
std::vector<double> RandomPositions(SplitMix64& rng, int frames, int joints) {
  std::vector<double> p(static_cast<size_t>(frames) * joints * 3, 0.0);
  const size_t stride = static_cast<size_t>(joints) * 3;
  for (int f = 0; f < frames; ++f) {
    const bool repeat = f > 0 && rng.OneIn(4);
    for (size_t c = 0; c < stride; ++c) {
      p[f * stride + c] = repeat ? p[(f - 1) * stride + c] : rng.Int(0, 3) + 0.25 * rng.Int(0, 1);
    }
  }
  return p;
}

int Drawings(const TimingMap& map) {
  int runs = 0;
  for (size_t t = 0; t < map.source_frames.size(); ++t) {
    runs += t == 0 || map.source_frames[t] != map.source_frames[t - 1];
  }
  return runs;
}

TEST(DrawingTargetTest, NaiveAndFastAgreeAndStopAtTheTarget) {
  SplitMix64 rng(2828);
  for (int clip = 0; clip < 1500; ++clip) {
    const int frames = rng.Int(2, 40);
    const int joints = rng.Int(1, 3);
    const std::vector<double> positions = RandomPositions(rng, frames, joints);
    ASSERT_OK_AND_ASSIGN(FrameDistance distance,
                         FrameDistance::Create(positions, frames, joints, {}));
    RetimeOptions options;
    options.omissions = frames >= 3 ? rng.Int(0, std::min(4, frames - 3)) : 0;
    options.max_hold = rng.Int(1, 4);
    options.holds = rng.OneIn(2) ? frames * options.max_hold : rng.Int(0, frames);
    options.keep_length = !rng.OneIn(4);
    options.order = rng.OneIn(4) ? StepOrder::kHoldThenOmit : StepOrder::kOmitThenHold;
    options.max_drawings = rng.Int(0, frames);
    ASSERT_THAT(ValidateRetimeOptions(options, frames), IsOk());
    const TimingMap naive = RetimeNaive(distance, options);
    const TimingMap fast = RetimeFast(distance, options);
    ASSERT_TRUE(naive == fast) << "clip " << clip;
    // Step B never takes a step once the target is met; so with omit-then-hold it never goes
    // below it by more than the omissions could not cause.
    if (options.max_drawings > 0 && naive.holds_applied > 0 &&
        options.order == StepOrder::kOmitThenHold) {
      RetimeOptions fewer = options;
      fewer.holds = naive.holds_applied - 1;
      EXPECT_GT(Drawings(RetimeNaive(distance, fewer)), options.max_drawings) << "clip " << clip;
    }
  }
}

TEST(DrawingTargetTest, OnThreesEveryRunButTheLastIsThree) {
  // Unbounded holds with max_hold 3 and a target of ceil(N / 3): the sequence ends on threes
  // but for its last runs (the last frame is never held, so the run before it may stay short).
  SplitMix64 rng(33);
  for (int clip = 0; clip < 200; ++clip) {
    const int frames = rng.Int(24, 120);
    const std::vector<double> positions = RandomPositions(rng, frames, 2);
    ASSERT_OK_AND_ASSIGN(FrameDistance distance, FrameDistance::Create(positions, frames, 2, {}));
    RetimeOptions options = DefaultRetimeOptions(frames);
    options.holds = 3 * frames;
    options.max_drawings = (frames + 2) / 3;
    const TimingMap map = RetimeFast(distance, options);
    std::vector<int> runs;
    for (size_t t = 0; t < map.source_frames.size(); ++t) {
      if (t == 0 || map.source_frames[t] != map.source_frames[t - 1]) runs.push_back(0);
      ++runs.back();
    }
    std::vector<int> sorted = runs;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted[(sorted.size() - 1) / 2], 3) << "clip " << clip;
    EXPECT_LE(static_cast<int>(runs.size()), options.max_drawings + 2) << "clip " << clip;
  }
}

// Positions of a clip of `frames` frames of one joint moving along x by `steps`.
std::vector<double> Line(const std::vector<double>& xs) {
  std::vector<double> p;
  for (double x : xs) {
    p.push_back(x);
    p.push_back(0);
    p.push_back(0);
  }
  return p;
}

TEST(RetimeShotsTest, ConcatenationIsTheShotsRetimedAlone) {
  SplitMix64 rng(5);
  for (int clip = 0; clip < 300; ++clip) {
    const int na = rng.Int(1, 30);
    const int nb = rng.Int(1, 30);
    std::vector<double> a = RandomPositions(rng, na, 2);
    std::vector<double> b = RandomPositions(rng, nb, 2);
    std::vector<double> ab = a;
    ab.insert(ab.end(), b.begin(), b.end());
    RetimeOptions oa = DefaultRetimeOptions(na);
    RetimeOptions ob = DefaultRetimeOptions(nb);
    oa.max_drawings = rng.Int(0, na);
    const std::optional<FilmGrid> no_grid;
    ASSERT_OK_AND_ASSIGN(ShotsRetimed shots,
                         RetimeShots(ab, na + nb, 2, {}, no_grid, true, {0, na}, {oa, ob}));
    TimingMap expected;
    for (int shot = 0; shot < 2; ++shot) {
      const std::vector<double>& p = shot == 0 ? a : b;
      const int n = shot == 0 ? na : nb;
      const int first = shot == 0 ? 0 : na;
      ASSERT_OK_AND_ASSIGN(FrameDistance d, FrameDistance::Create(p, n, 2, {}));
      TimingMap alone;
      if (n >= kMinRetimedShotFrames) {
        alone = RetimeNaive(d, shot == 0 ? oa : ob);
      } else {
        for (int k = 0; k < n; ++k) {
          alone.source_frames.push_back(k);
          alone.kinds.push_back(FrameKind::kOriginal);
        }
      }
      for (int32_t s : alone.source_frames) expected.source_frames.push_back(s + first);
      expected.kinds.insert(expected.kinds.end(), alone.kinds.begin(), alone.kinds.end());
      for (int32_t s : alone.deleted) expected.deleted.push_back(s + first);
      for (int32_t s : alone.hidden) expected.hidden.push_back(s + first);
      expected.omissions_applied += alone.omissions_applied;
      expected.duplicates_applied += alone.duplicates_applied;
      expected.duplicates_skipped += alone.duplicates_skipped;
      expected.holds_applied += alone.holds_applied;
      expected.duplicates_omitted += alone.duplicates_omitted;
      expected.duplicates_held += alone.duplicates_held;
    }
    ASSERT_TRUE(shots.map == expected) << "clip " << clip;
    ASSERT_EQ(shots.input_ssd.size(), static_cast<size_t>(na + nb));
  }
}

TEST(RetimeShotsTest, GridShotsStartOnTheirOwnGridAndTheJumpIsInTheSsd) {
  // 120 fps: a lone calibration frame (x = 100), then 21 frames of a line.
  std::vector<double> xs{100};
  for (int k = 0; k < 21; ++k) xs.push_back(0.1 * k * k);
  const std::vector<double> p = Line(xs);
  const std::optional<FilmGrid> grid = FilmGrid::Make(120, 24);
  ASSERT_TRUE(grid.has_value());
  RetimeOptions none;
  none.omissions = 0;
  none.holds = 0;
  RetimeOptions walk = DefaultRetimeOptions(5);  // 21 frames at 120 fps: 5 grid frames
  ASSERT_OK_AND_ASSIGN(ShotsRetimed shots,
                       RetimeShots(p, 22, 1, {}, grid, true, {0, 1}, {none, walk}));
  ASSERT_EQ(shots.map.source_frames.size(), 22u);
  EXPECT_EQ(shots.map.source_frames[0], 0);  // the calibration frame, as it went in
  EXPECT_EQ(shots.map.kinds[0], FrameKind::kOriginal);
  EXPECT_NE(shots.map.source_frames[1], 0);  // the walk starts on the next source frame
  EXPECT_THAT(shots.grid_samples, ElementsAre(0, 1, 6, 11, 16, 21));
  ASSERT_EQ(shots.input_ssd.size(), 6u);
  EXPECT_EQ(shots.input_ssd[0], 0.0);
  EXPECT_EQ(shots.input_ssd[1], 100.0 * 100.0);  // dist(frame 0, frame 1 = x 0)
  EXPECT_EQ(shots.grid_frames[0], 0);
  EXPECT_EQ(shots.grid_frames[1], 1);
}

TEST(SourceSsdTest, SameBitsAsInputSsdAcrossChunks) {
  SplitMix64 rng(9);
  const int frames = 9000;  // three chunks
  std::vector<double> p(static_cast<size_t>(frames) * 2 * 3);
  for (double& v : p) v = rng.Unit();
  DistanceOptions options;
  options.root_relative = true;
  ASSERT_OK_AND_ASSIGN(FrameDistance whole, FrameDistance::Create(p, frames, 2, options));
  ASSERT_OK_AND_ASSIGN(std::vector<double> ssd, SourceSsd(p, frames, 2, options));
  EXPECT_TRUE(ssd == whole.InputSsd());
}

}  // namespace
}  // namespace koma

// Named behaviours of RetimeSkeletal (docs/semantics.md, "RetimeSkeletal"), each on a tiny 1D clip
// whose result is worked out by hand. Every case runs both implementations and checks they agree.
#include "core/retime.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "core/distance.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::ElementsAreArray;
using ::testing::HasSubstr;

constexpr FrameKind O = FrameKind::kOriginal;
constexpr FrameKind D = FrameKind::kDuplicate;
constexpr FrameKind H = FrameKind::kHeld;

// One joint moving along x: SSD(k) = (xs[k] - xs[k-1])^2.
FrameDistance Line(const std::vector<double>& xs) {
  std::vector<double> positions;
  for (double x : xs) positions.insert(positions.end(), {x, 0.0, 0.0});
  return FrameDistance::Create(positions, static_cast<int>(xs.size()), 1, {}).value();
}

RetimeOptions Options(int omissions, int holds, int max_hold = 3, bool keep_length = true) {
  RetimeOptions options;
  options.omissions = omissions;
  options.holds = holds;
  options.max_hold = max_hold;
  options.keep_length = keep_length;
  return options;
}

// Runs both implementations; they must agree.
TimingMap Retime(const FrameDistance& distance, const RetimeOptions& options) {
  EXPECT_THAT(ValidateRetimeOptions(options, distance.frame_count()), IsOk());
  const TimingMap naive = RetimeNaive(distance, options);
  const TimingMap fast = RetimeFast(distance, options);
  EXPECT_TRUE(naive == fast) << "RetimeNaive and RetimeFast disagree";
  return fast;
}

// A 1D swing: steps 1, 5, 4, 4, 4 (frames 1-5, the fast part), 1, 1, 1, 4.5 (frame 9), 1,
// then a still ending of 0.5 steps where duplicates go.
const std::vector<double> kSwing = {0, 1, 6, 10, 14, 18, 19, 20, 21, 25.5, 26.5, 27, 27.5, 28};

TEST(RetimeTest, Fig3IterativeOmissionDeletesTheConsecutiveFastFrames) {
  const TimingMap map = Retime(Line(kSwing), Options(4, 0));
  // Deleting frame 2 merges its step into frame 3's: (5 + 4)^2 = 81, then 13^2, then 17^2.
  EXPECT_THAT(map.deleted, ElementsAre(2, 3, 4, 5));
  EXPECT_EQ(map.omissions_applied, 4);
  EXPECT_THAT(map.source_frames, ElementsAre(0, 1, 6, 7, 8, 9, 10, 10, 10, 11, 11, 11, 12, 13));
}

TEST(RetimeTest, Fig3OneShotTopFourSsdWouldPickAnotherSet) {
  const std::vector<double> ssd = Line(kSwing).InputSsd();
  std::vector<int> frames(ssd.size() - 2);
  std::iota(frames.begin(), frames.end(), 1);  // 1 .. N-2, the deletable frames
  std::stable_sort(frames.begin(), frames.end(), [&](int a, int b) { return ssd[a] > ssd[b]; });
  std::vector<int> top4(frames.begin(), frames.begin() + 4);
  std::sort(top4.begin(), top4.end());
  EXPECT_THAT(top4, ElementsAre(2, 3, 4, 9));  // frame 9's 4.5^2 beats frames 4 and 5
}

TEST(RetimeTest, DeletingARunHeadLeavesItsDuplicateShown) {
  // The swing without its still ending: the stillest gap (SSD 1, smallest t) after three
  // deletes is right after frame 5, so frame 5 gets a duplicate before the fourth delete
  // removes its original slot. Frame 5 stays on screen and is not "deleted".
  const TimingMap map =
      Retime(Line({0, 1, 6, 10, 14, 18, 19, 20, 21, 25.5, 26.5, 27.5}), Options(4, 0));
  EXPECT_EQ(map.omissions_applied, 4);
  EXPECT_THAT(map.deleted, ElementsAre(2, 3, 4));
  EXPECT_THAT(map.source_frames, ElementsAre(0, 0, 0, 1, 5, 5, 6, 7, 8, 9, 10, 11));
  EXPECT_THAT(map.kinds, ElementsAre(O, D, D, O, D, D, O, O, O, O, O, O));
}

TEST(RetimeTest, OmissionsLandInFastPartsAndDuplicatesInStillOnes) {
  // Steps 2, 0.1, 2, 0.2, 2, 9, 10, 11, 2, 2.
  const FrameDistance distance = Line({0, 2, 2.1, 4.1, 4.3, 6.3, 15.3, 25.3, 36.3, 38.3, 40.3});
  const TimingMap map = Retime(distance, Options(3, 0));
  EXPECT_THAT(map.deleted, ElementsAre(7, 8, 9));
  // Duplicates stack after frame 1 (the stillest gap, 0.1) up to max_hold = 3 frames, then
  // move to the next stillest gap (0.2, after frame 3).
  EXPECT_THAT(map.source_frames, ElementsAre(0, 1, 1, 1, 2, 3, 3, 4, 5, 6, 10));
  EXPECT_THAT(map.kinds, ElementsAre(O, O, D, D, O, O, D, O, O, O, O));
  EXPECT_EQ(map.duplicates_applied, 3);
  EXPECT_EQ(map.duplicates_skipped, 0);
}

TEST(RetimeTest, HoldsLandInTheSlowestPart) {
  // Steps 10, 10, 10, then 1/8, 2/8, 3/8 (exact in binary), then 9.25, 10, 10.
  const FrameDistance distance = Line({0, 10, 20, 30, 30.125, 30.375, 30.75, 40, 50, 60});
  const TimingMap map = Retime(distance, Options(0, 2));
  // Frame 4 (1/8 away) is held first; then frame 5 (now 3/8 from frame 3) and frame 6 (3/8
  // from frame 5) tie exactly and the smaller t wins.
  EXPECT_THAT(map.source_frames, ElementsAre(0, 1, 2, 3, 3, 3, 6, 7, 8, 9));
  EXPECT_THAT(map.kinds, ElementsAre(O, O, O, O, H, H, O, O, O, O));
  EXPECT_THAT(map.hidden, ElementsAre(4, 5));
  EXPECT_TRUE(map.deleted.empty());
  EXPECT_EQ(map.holds_applied, 2);
}

TEST(RetimeTest, KeepLengthKeepsTheFrameCount) {
  const TimingMap map = Retime(Line(kSwing), Options(4, 3));
  EXPECT_EQ(map.source_frames.size(), kSwing.size());
  EXPECT_EQ(map.kinds.size(), kSwing.size());
}

TEST(RetimeTest, WithoutKeepLengthEachDeleteShortensTheClip) {
  const TimingMap map = Retime(Line(kSwing), Options(4, 3, 3, /*keep_length=*/false));
  EXPECT_EQ(map.source_frames.size(), kSwing.size() - 4);
  EXPECT_EQ(map.duplicates_applied + map.duplicates_skipped, 0);
}

TEST(RetimeTest, NoCreatedRunIsLongerThanMaxHold) {
  // A clip that is almost still everywhere: holds and duplicates would like to pile up.
  std::vector<double> xs(30);
  for (size_t k = 0; k < xs.size(); ++k) xs[k] = 0.001 * static_cast<double>(k * k);
  const TimingMap map = Retime(Line(xs), Options(5, 30, /*max_hold=*/2));
  int longest = 0;
  for (size_t t = 0, run = 0; t < map.source_frames.size(); ++t) {
    run = (t > 0 && map.source_frames[t] == map.source_frames[t - 1]) ? run + 1 : 1;
    longest = std::max(longest, static_cast<int>(run));
  }
  EXPECT_EQ(longest, 2);
}

TEST(RetimeTest, MaxHoldOneForbidsHoldsAndDuplicates) {
  const TimingMap map = Retime(Line(kSwing), Options(2, 5, /*max_hold=*/1));
  EXPECT_EQ(map.omissions_applied, 2);
  EXPECT_EQ(map.duplicates_skipped, 2);
  EXPECT_EQ(map.holds_applied, 0);
  EXPECT_EQ(map.source_frames.size(), kSwing.size() - 2);
}

TEST(RetimeTest, FirstAndLastPosesSurviveAFastEnding) {
  // The last step is by far the fastest, the first the stillest.
  const TimingMap map = Retime(Line({0, 0.01, 1, 2, 3, 4, 100}), Options(4, 7));
  EXPECT_EQ(map.source_frames.front(), 0);
  EXPECT_EQ(map.kinds.front(), O);
  EXPECT_EQ(map.source_frames.back(), 6);
  EXPECT_EQ(map.kinds.back(), O);
}

TEST(RetimeTest, LastPoseIsNeverHeldEvenWhenStillest) {
  const TimingMap map = Retime(Line({0, 5, 10, 15, 15.001}), Options(0, 5));
  EXPECT_EQ(map.source_frames.back(), 4);
  EXPECT_EQ(map.kinds.back(), O);
}

TEST(RetimeTest, OmissionsStopWhenNothingMoves) {
  const TimingMap still = Retime(Line({2, 2, 2, 2, 2, 2}), Options(3, 0));
  EXPECT_EQ(still.omissions_applied, 0);
  EXPECT_EQ(still.duplicates_applied, 0);
  EXPECT_THAT(still.source_frames, ElementsAre(0, 1, 2, 3, 4, 5));
  // One step in the middle: frames 3 and 4 go (each time the jump moves one frame right),
  // then only the last frame differs from its predecessor and it cannot be deleted.
  const TimingMap step = Retime(Line({0, 0, 0, 1, 1, 1}), Options(3, 0, 3, false));
  EXPECT_EQ(step.omissions_applied, 2);
  EXPECT_THAT(step.deleted, ElementsAre(3, 4));
  EXPECT_THAT(step.source_frames, ElementsAre(0, 1, 2, 5));
}

TEST(RetimeTest, HoldsStopWhenNoCandidateRemains) {
  // 4 frames, max_hold 2: only t = 1 and t = 2 can be held, and holding t = 1 makes a run
  // of 2 that blocks t = 2.
  const TimingMap map = Retime(Line({0, 1, 3, 6}), Options(0, 10, 2));
  EXPECT_EQ(map.holds_applied, 1);
  EXPECT_THAT(map.source_frames, ElementsAre(0, 0, 2, 3));
}

TEST(RetimeTest, NoStepsIsTheIdentity) {
  const TimingMap map = Retime(Line(kSwing), Options(0, 0));
  std::vector<int32_t> identity(kSwing.size());
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_THAT(map.source_frames, ElementsAreArray(identity));
  EXPECT_TRUE(std::all_of(map.kinds.begin(), map.kinds.end(), [](FrameKind k) { return k == O; }));
}

// Steps 3.5, 0.1, 2.9, 1, 1.
const std::vector<double> kOrderClip = {0, 3.5, 3.6, 6.5, 7.5, 8.5};

TEST(RetimeTest, OmitThenHoldDeletesFirst) {
  const TimingMap map = Retime(Line(kOrderClip), Options(1, 1, 3, false));
  // Delete frame 1 (12.25); then the stillest head is frame 4 (1; frame 2 is now 3.6 from 0).
  EXPECT_THAT(map.source_frames, ElementsAre(0, 2, 3, 3, 5));
  EXPECT_THAT(map.kinds, ElementsAre(O, O, O, H, O));
  EXPECT_THAT(map.deleted, ElementsAre(1));
  EXPECT_THAT(map.hidden, ElementsAre(4));
}

TEST(RetimeTest, HoldThenOmitHoldsFirstAndADeletedHeadLeavesItsHeldCopy) {
  RetimeOptions options = Options(1, 1, 3, false);
  options.order = StepOrder::kHoldThenOmit;
  const TimingMap map = Retime(Line(kOrderClip), options);
  // Hold frame 2 (0.01) -> 0 1 1h 3 4 5; delete t = 1 (12.25): frame 1 is still shown by the
  // held copy, so nothing is "deleted".
  EXPECT_THAT(map.source_frames, ElementsAre(0, 1, 3, 4, 5));
  EXPECT_THAT(map.kinds, ElementsAre(O, H, O, O, O));
  EXPECT_TRUE(map.deleted.empty());
  EXPECT_THAT(map.hidden, ElementsAre(2));
}

TEST(RetimeTest, DefaultOptionsFollowThePaper) {
  const RetimeOptions options = DefaultRetimeOptions(129);
  EXPECT_EQ(options.omissions, 4);
  EXPECT_EQ(options.holds, 43);
  EXPECT_EQ(options.max_hold, 3);
  EXPECT_TRUE(options.keep_length);
  EXPECT_EQ(options.order, StepOrder::kOmitThenHold);
  EXPECT_EQ(DefaultRetimeOptions(5).omissions, 2);
  EXPECT_EQ(DefaultRetimeOptions(2).omissions, 0);
  for (int n = 2; n <= 200; ++n) {
    EXPECT_THAT(ValidateRetimeOptions(DefaultRetimeOptions(n), n), IsOk()) << n;
  }
}

TEST(RetimeTest, ValidateNamesTheOptionAndValue) {
  using absl::StatusCode;
  EXPECT_THAT(ValidateRetimeOptions(Options(0, 0), 1),
              StatusIs(StatusCode::kInvalidArgument, HasSubstr("frame_count: 1 must be >= 2")));
  EXPECT_THAT(ValidateRetimeOptions(Options(-1, 0), 10),
              StatusIs(StatusCode::kInvalidArgument, HasSubstr("omissions: -1 is negative")));
  EXPECT_THAT(ValidateRetimeOptions(Options(200, 0), 129),
              StatusIs(StatusCode::kOutOfRange,
                       HasSubstr("omissions: 200 must be < frame_count - 2 = 127 (frames 0 and "
                                 "128 are never deleted)")));
  EXPECT_THAT(ValidateRetimeOptions(Options(127, 0), 129),
              StatusIs(StatusCode::kOutOfRange, HasSubstr("omissions: 127")));
  EXPECT_THAT(ValidateRetimeOptions(Options(126, 0), 129), IsOk());
  EXPECT_THAT(ValidateRetimeOptions(Options(0, 0), 2), IsOk());
  EXPECT_THAT(ValidateRetimeOptions(Options(0, -3), 10),
              StatusIs(StatusCode::kInvalidArgument, HasSubstr("holds: -3 is negative")));
  EXPECT_THAT(ValidateRetimeOptions(Options(0, 0, 0), 10),
              StatusIs(StatusCode::kInvalidArgument, HasSubstr("max_hold: 0 must be >= 1")));
}

TEST(RetimeTest, TimingMapEqualityComparesEveryField) {
  const TimingMap base = Retime(Line(kSwing), Options(2, 2));
  TimingMap other = base;
  EXPECT_TRUE(base == other);
  other.duplicates_skipped += 1;
  EXPECT_FALSE(base == other);
  other = base;
  other.duplicates_omitted += 1;
  EXPECT_FALSE(base == other);
  other = base;
  other.duplicates_held += 1;
  EXPECT_FALSE(base == other);
  other = base;
  other.kinds.back() = H;
  EXPECT_FALSE(base == other);
  other = base;
  other.hidden.push_back(99);
  EXPECT_FALSE(base == other);
}

}  // namespace
}  // namespace koma

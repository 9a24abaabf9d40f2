// Auto-blink (beyond the paper): nothing when disabled; visible on a flat open eye; intervals
// within [mean - spread, mean + spread] fps; the timer restarting at every blink; keep
// intervals; never touching a detected blink; determinism with a golden walk.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"
#include "tests/core/lip_blink_test_util.h"

namespace koma {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;

EyeOptions AutoOptions(double mean_s, double spread_s, int hold = 2) {
  EyeOptions options;
  options.auto_blink.enabled = true;
  options.auto_blink.mean_interval_s = mean_s;
  options.auto_blink.spread_s = spread_s;
  options.auto_blink.hold = hold;
  return options;
}

std::vector<int> Starts(const std::vector<Blink>& blinks, bool automatic = true) {
  std::vector<int> starts;
  for (const Blink& b : blinks) {
    if (b.automatic == automatic) starts.push_back(b.closed_begin);
  }
  return starts;
}

TEST(AutoBlinkTest, DisabledInsertsNothing) {
  const std::vector<double> flat(3000, 1.0);
  const EyeResult r = ConvertEyes({flat}, EyeOptions(), 1);
  EXPECT_TRUE(r.blinks[0].empty());
  EXPECT_EQ(r.values[0], flat);
}

TEST(AutoBlinkTest, AFlatOpenEyeBlinksClosedThenHalfOpenThenOpen) {
  const std::vector<double> flat(600, 1.0);
  for (int hold = 1; hold <= 3; ++hold) {
    const EyeResult r = ConvertEyes({flat}, AutoOptions(4.0, 1.0, hold), 5);
    ASSERT_GE(r.blinks[0].size(), 3u);
    EXPECT_EQ(r.closed[0], 0.0);  // flat and no min: closes at 0
    const std::string drawn = Letters(r.values[0]);
    for (const Blink& b : r.blinks[0]) {
      const int s = b.closed_begin;
      EXPECT_EQ(b, (Blink{s, s, s + hold - 1, hold, hold, true}));
      EXPECT_EQ(drawn.substr(s - 1, 2 * hold + 2),
                "O" + std::string(hold, 'C') + std::string(hold, 'm') + "O");
    }
  }
}

// SplitMix64(2019 ^ kAutoBlinkStream), u = top 53 bits / 2^53, round((4 + (2u - 1)) 30):
// computed independently of koma (Python). Intervals 136, 133, 95, 102, 132, 130, 131, 108.
TEST(AutoBlinkTest, GoldenWalkForSeed2019) {
  const std::vector<double> flat(1000, 1.0);
  const EyeResult r = ConvertEyes({flat}, AutoOptions(4.0, 1.0), 2019);
  EXPECT_THAT(Starts(r.blinks[0]), ElementsAre(136, 273, 372, 478, 614, 748, 883, 995));
}

TEST(AutoBlinkTest, IntervalsStayWithinMeanPlusOrMinusSpread) {
  struct Case {
    double fps, mean, spread;
    int shortest, longest;  // round((mean -+ spread) fps)
  };
  for (const Case& c : {Case{30.0, 4.0, 1.0, 90, 150}, Case{24.0, 2.5, 0.5, 48, 72}}) {
    std::vector<int> intervals;
    for (uint64_t seed = 0; seed < 20; ++seed) {
      EyeOptions options = AutoOptions(c.mean, c.spread);
      options.fps = c.fps;
      const EyeResult r = ConvertEyes({std::vector<double>(20000, 1.0)}, options, seed);
      int end = 0;  // the timer starts at frame 0, restarts at each blink's end
      for (const Blink& b : r.blinks[0]) {
        intervals.push_back(b.closed_begin - end);
        end = b.closed_begin + 2 * b.hold;
      }
    }
    ASSERT_GT(intervals.size(), 1000u);
    const auto [lo, hi] = std::minmax_element(intervals.begin(), intervals.end());
    EXPECT_GE(*lo, c.shortest);
    EXPECT_LE(*hi, c.longest);
    EXPECT_LE(*lo, c.shortest + 2);  // the whole range is used
    EXPECT_GE(*hi, c.longest - 2);
    double sum = 0.0;
    for (int i : intervals) sum += i;
    EXPECT_NEAR(sum / intervals.size(), c.mean * c.fps, 1.5);
  }
}

TEST(AutoBlinkTest, TheWalkStopsWhenABlinkNoLongerFitsTheClip) {
  // Spread 0: every interval is 120 frames; blinks at 120 and 244 need 248 frames.
  EXPECT_THAT(Starts(ConvertEyes({std::vector<double>(248, 1.0)}, AutoOptions(4, 0), 1).blinks[0]),
              ElementsAre(120, 244));
  EXPECT_THAT(Starts(ConvertEyes({std::vector<double>(247, 1.0)}, AutoOptions(4, 0), 1).blinks[0]),
              ElementsAre(120));
}

TEST(AutoBlinkTest, EveryDetectedBlinkRestartsTheTimer) {
  // 'hCChh' at 100: a blink painted on [100, 105); the timer restarts at 105.
  const std::vector<double> eye = Eye(std::string(100, 'O') + "hCChh" + std::string(400, 'O'));
  const EyeResult r = ConvertEyes({eye}, AutoOptions(4, 0), 1);
  EXPECT_THAT(Starts(r.blinks[0], false), ElementsAre(101));
  EXPECT_THAT(Starts(r.blinks[0]), ElementsAre(225, 349, 473));
  // The first candidate, 120, has the guard window [119, 124]: a detected blink beginning at
  // 124 touches it (the timer restarts at that blink's end, 127), one at 125 does not.
  const auto first_auto = [](int blink_at) {
    const std::vector<double> e = Eye(std::string(blink_at, 'O') + "CC" + std::string(300, 'O'));
    return Starts(ConvertEyes({e}, AutoOptions(4, 0), 1).blinks[0]).front();
  };
  EXPECT_EQ(first_auto(124), 127 + 120);
  EXPECT_EQ(first_auto(125), 120);
}

TEST(AutoBlinkTest, KeepIntervalsMoveTheBlinkJustPastThem) {
  struct Case {
    FrameInterval keep;
    int first;
  };
  // The candidate 120 and its guard window [119, 124] (spread 0).
  for (const Case& c : {Case{{100, 119}, 120}, Case{{100, 120}, 121}, Case{{124, 130}, 131},
                        Case{{125, 130}, 120}, Case{{0, 200}, 201}}) {
    EyeOptions options = AutoOptions(4, 0);
    options.auto_blink.keep = {c.keep};
    const EyeResult r = ConvertEyes({std::vector<double>(400, 1.0)}, options, 1);
    ASSERT_FALSE(r.blinks[0].empty());
    EXPECT_EQ(r.blinks[0][0].closed_begin, c.first) << c.keep.begin << ".." << c.keep.end;
  }
}

// Random eyes with detected blinks and random keep intervals: the detected blinks survive as
// they are; every inserted one fits the clip, its window [s - 1, s + 2 hold] touches no
// detected blink's span and no keep interval, and it comes a drawn interval after the
// previous blink's end (later only when a keep interval pushed it: then s - 1 is its end).
TEST(AutoBlinkTest, InsertedBlinksTouchNeitherDetectedBlinksNorKeepIntervals) {
  for (uint64_t trial = 0; trial < 200; ++trial) {
    SplitMix64 rng(trial);
    const int frame_count = 200 + rng.Int(0, 1500);
    const RandomEye eye = MakeRandomEye(rng, frame_count, 3);
    EyeOptions options = AutoOptions(1.5, 1.0, rng.Int(1, 3));  // intervals of 15-75 frames
    options.min = 0.0;
    options.max = 1.0;
    for (int f = rng.Int(0, 60); f < frame_count - 10; f += rng.Int(30, 200)) {
      const int end = std::min(f + rng.Int(1, 40), frame_count);  // valid: within the clip
      options.auto_blink.keep.push_back({f, end});
      f = end;
    }
    const std::vector<Blink> detected = ConvertEyes({eye.values}, LetterOptions(), 1).blinks[0];
    ASSERT_TRUE(ValidateEyeOptions(options, frame_count).ok());
    const EyeResult r = ConvertEyes({eye.values}, options, trial);
    const std::vector<Blink>& all = r.blinks[0];
    std::vector<Blink> kept;
    for (const Blink& b : all) {
      if (!b.automatic) kept.push_back(b);
    }
    ASSERT_THAT(kept, ElementsAreArray(detected)) << "trial " << trial;
    std::vector<std::pair<int, int>> obstacles;  // [first, last] frames
    for (size_t i = 0; i < detected.size(); ++i) {
      obstacles.push_back({detected[i].closing_begin, SpanEnd(detected, i, frame_count) - 1});
    }
    std::set<int> keep_ends;
    for (const FrameInterval& k : options.auto_blink.keep) {
      obstacles.push_back({k.begin, k.end - 1});
      keep_ends.insert(k.end);
    }
    int previous_end = 0;
    for (size_t i = 0; i < all.size(); ++i) {
      const Blink& b = all[i];
      const int s = b.closed_begin;
      if (b.automatic) {
        ASSERT_LE(s + 2 * b.hold, frame_count);
        for (const auto& [first, last] : obstacles) {
          ASSERT_TRUE(last < s - 1 || first > s + 2 * b.hold)
              << "trial " << trial << ": blink at " << s << " touches [" << first << ", " << last
              << "]";
        }
        EXPECT_GE(s - previous_end, 15) << "trial " << trial;
        EXPECT_TRUE(s - previous_end <= 75 || keep_ends.count(s - 1) != 0) << "trial " << trial;
      }
      previous_end = b.automatic ? s + 2 * b.hold : SpanEnd(all, i, frame_count);
      if (i > 0) {
        ASSERT_LT(all[i - 1].closed_begin, s);
      }
    }
    ExpectAnimeBlinks(eye.values, r.values[0], all, {0.0, 0.5, 1.0}, true);
  }
}

// An inserted blink's open drawing is the input's level where it goes (docs/semantics.md,
// "LipBlink", "Open levels"): on an eye open at 1 with one blink (closed at 0) and a brief
// overshoot to 1.2 (E_max), then squinting at 0.8, each inserted blink is half-open at half
// the level there and leaves the input as it was around it. Before, every one was half-open
// at 0.6, half of E_max.
TEST(AutoBlinkTest, AnInsertedBlinkOpensToTheInputsLevelThere) {
  std::vector<double> eye(300, 1.0);
  eye[5] = eye[8] = 0.5;
  eye[6] = eye[7] = 0.0;
  eye[20] = 1.1;
  eye[21] = 1.2;
  eye[22] = 1.1;
  eye.insert(eye.end(), 400, 0.8);
  const EyeResult r = ConvertEyes({eye}, AutoOptions(2, 0.5, 2), 3);
  ASSERT_GE(r.blinks[0].size(), 6u);
  ASSERT_EQ(r.levels[0].size(), r.blinks[0].size());
  EXPECT_FALSE(r.blinks[0][0].automatic);
  int squinting = 0;
  for (size_t i = 1; i < r.blinks[0].size(); ++i) {
    const Blink& b = r.blinks[0][i];
    ASSERT_TRUE(b.automatic);
    const int s = b.closed_begin;
    const double level = eye[s + 4];  // the frame after it: open, 1 or 0.8
    EXPECT_EQ(r.levels[0][i].before, level);
    EXPECT_EQ(r.levels[0][i].after, level);
    EXPECT_EQ(r.values[0][s - 1], eye[s - 1]);
    EXPECT_EQ(std::vector<double>(r.values[0].begin() + s, r.values[0].begin() + s + 4),
              (std::vector<double>{0.0, 0.0, level / 2, level / 2}))
        << "blink at " << s;
    EXPECT_EQ(r.values[0][s + 4], eye[s + 4]);
    squinting += level == 0.8;
  }
  EXPECT_GE(squinting, 2);
  EXPECT_LT(squinting, static_cast<int>(r.blinks[0].size()) - 1);
}

TEST(AutoBlinkTest, SameSeedSameBlinksDifferentSeedsDifferentBlinks) {
  const std::vector<double> flat(3000, 1.0);
  const EyeResult a = ConvertEyes({flat}, AutoOptions(4, 1), 77);
  EXPECT_EQ(ConvertEyes({flat}, AutoOptions(4, 1), 77).values, a.values);
  EXPECT_NE(Starts(ConvertEyes({flat}, AutoOptions(4, 1), 78).blinks[0]), Starts(a.blinks[0]));
}

TEST(AutoBlinkTest, LinkedCurvesShareTheBlinksUnlinkedOnesEachDrawTheSameStream) {
  const std::vector<double> left(2000, 1.0);
  const std::vector<double> right(2000, 0.8);
  EyeOptions options = AutoOptions(4, 1);
  const EyeResult linked = ConvertEyes({left, right}, options, 9);
  ASSERT_FALSE(linked.blinks[0].empty());
  EXPECT_EQ(linked.blinks[1], linked.blinks[0]);
  options.linked = false;
  // Each curve from SplitMix64(seed ^ kAutoBlinkStream) afresh: a curve's blinks do not
  // depend on the others; flat curves blink together.
  const EyeResult unlinked = ConvertEyes({left, right}, options, 9);
  EXPECT_EQ(unlinked.blinks[0], linked.blinks[0]);
  EXPECT_EQ(unlinked.blinks[1], linked.blinks[0]);
}

}  // namespace
}  // namespace koma

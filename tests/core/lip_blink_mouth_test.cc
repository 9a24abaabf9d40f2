// ConvertMouth (docs/semantics.md, "LipBlink", paper section 3.2.1, Fig. 5): three levels, the
// state diagram (never the same shape twice, closed before each interval), holds of n frames,
// FOLLOW on hand-built inputs, speech detection, determinism with a golden RANDOM sequence, and the
// options' validation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// The holds' shapes as letters: C closed, M mid, O open.
std::string Letters(const std::vector<MouthHold>& holds) {
  std::string s;
  for (const MouthHold& h : holds) s += "CMO"[static_cast<int>(h.shape)];
  return s;
}

// A talking mouth: silence, then speech intervals of random values in [0, 1] (frames 30-99,
// 130-219, 260-389), silence between; 420 frames, min 0 and max 1 exactly.
std::vector<double> Talking(uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<double> m(420, 0.0);
  const std::pair<int, int> speech[] = {{30, 100}, {130, 220}, {260, 390}};
  for (const auto& [b, e] : speech) {
    for (int f = b; f < e; ++f) m[f] = 0.05 + 0.9 * rng.Unit();
  }
  m[40] = 1.0;
  return m;
}

TEST(ConvertMouthTest, OnlyThreeLevelsInsideSpeechAndTheInputOutside) {
  const std::vector<double> m = Talking(1);
  MouthOptions options;
  options.mid_ratio = 0.25;
  const MouthResult r = ConvertMouth(m, options, 7);
  EXPECT_EQ(r.closed, 0.0);
  EXPECT_EQ(r.open, 1.0);
  EXPECT_EQ(r.mid, 0.25);
  ASSERT_EQ(r.values.size(), m.size());
  std::vector<bool> inside(m.size(), false);
  for (const FrameInterval& v : r.speech) {
    for (int f = v.begin; f < v.end; ++f) inside[f] = true;
  }
  std::set<double> levels;
  for (size_t f = 0; f < m.size(); ++f) {
    if (inside[f]) {
      levels.insert(r.values[f]);
    } else {
      EXPECT_EQ(r.values[f], m[f]) << "frame " << f << " is outside speech";
    }
  }
  EXPECT_THAT(levels, ElementsAre(0.0, 0.25, 1.0));
}

TEST(ConvertMouthTest, LevelsAreTheCurvesMinAndMaxWhereverTheyAre) {
  for (int size = 1; size <= 11; ++size) {
    for (int lo = 0; lo < size; ++lo) {
      for (int hi = 0; hi < size; ++hi) {
        std::vector<double> m(static_cast<size_t>(size), 0.5);
        m[lo] = -2.0;
        m[hi] = 3.0;  // overwrites the minimum when hi == lo
        const MouthResult r = ConvertMouth(m, MouthOptions(), 1);
        EXPECT_EQ(r.closed, *std::min_element(m.begin(), m.end())) << size << " " << lo;
        EXPECT_EQ(r.open, 3.0) << size << " " << hi;
      }
    }
  }
}

TEST(ConvertMouthTest, NeverTheSameShapeTwiceAndEachIntervalOpensMidOrOpen) {
  const std::vector<double> m = Talking(2);
  for (MouthMode mode : {MouthMode::kRandom, MouthMode::kFollow}) {
    for (uint64_t seed = 0; seed < 200; ++seed) {
      MouthOptions options;
      options.mode = mode;
      options.frames_per_shape = 1 + static_cast<int>(seed % 4);
      const MouthResult r = ConvertMouth(m, options, seed);
      ASSERT_FALSE(r.holds.empty());
      std::set<int> interval_starts;
      for (const FrameInterval& v : r.speech) interval_starts.insert(v.begin);
      for (size_t i = 0; i < r.holds.size(); ++i) {
        const MouthHold& h = r.holds[i];
        if (interval_starts.count(h.begin) != 0) {
          EXPECT_NE(h.shape, MouthShape::kClosed) << "seed " << seed << " hold " << i;
        } else {
          ASSERT_GT(i, 0u);
          EXPECT_NE(h.shape, r.holds[i - 1].shape) << "seed " << seed << " hold " << i;
        }
        const double level = h.shape == MouthShape::kClosed ? r.closed
                             : h.shape == MouthShape::kMid  ? r.mid
                                                            : r.open;
        for (int f = h.begin; f < h.begin + h.length; ++f) ASSERT_EQ(r.values[f], level);
      }
    }
  }
}

TEST(ConvertMouthTest, HoldsAreNFramesExceptAShorterLastOneAtEachIntervalEnd) {
  const std::vector<double> m(100, 0.5);
  for (int n = 1; n <= 6; ++n) {
    MouthOptions options;
    options.frames_per_shape = n;
    options.speech = {{3, 4}, {10, 27}, {27, 40}, {50, 50 + 3 * n}, {90, 100}};
    const MouthResult r = ConvertMouth(m, options, 11);
    size_t i = 0;
    for (const FrameInterval& v : options.speech) {
      for (int b = v.begin; b < v.end; b += n, ++i) {  // the holds tile the interval exactly
        ASSERT_LT(i, r.holds.size());
        EXPECT_EQ(r.holds[i].begin, b) << "n " << n;
        EXPECT_EQ(r.holds[i].length, std::min(n, v.end - b)) << "n " << n << " at " << b;
      }
    }
    EXPECT_EQ(i, r.holds.size()) << "n " << n;
  }
}

TEST(ConvertMouthTest, AHugeNGivesOneHoldPerInterval) {
  MouthOptions options;
  options.frames_per_shape = INT_MAX;
  options.speech = {{0, 5}, {7, 20}};
  const MouthResult r = ConvertMouth(std::vector<double>(20, 0.0), options, 1);
  ASSERT_EQ(r.holds.size(), 2u);
  EXPECT_EQ(r.holds[0].length, 5);
  EXPECT_EQ(r.holds[1].begin, 7);
  EXPECT_EQ(r.holds[1].length, 13);
}

TEST(ConvertMouthTest, FollowPicksTheAllowedShapeNearestTheHoldsMean) {
  // Levels 0, 0.5, 1; holds of two frames. Each comment: the previous shape, the two allowed,
  // the hold's mean, the pick.
  const std::vector<double> m = {
      0.9,  0.9,   // C -> {M, O}, 0.9: O
      0.8,  0.8,   // O -> {C, M}, 0.8: M
      0.25, 0.25,  // M -> {C, O}, 0.25: C
      0.75, 0.75,  // C -> {M, O}, 0.75: a tie, M (the more closed)
      1.0,  1.0,   // M -> {C, O}, 1: O
      0.25, 0.25,  // O -> {C, M}, 0.25: a tie, C
      0.0,  0.0,   // C -> {M, O}, 0: M (nearest allowed, though C is nearer)
      0.0,  1.0,   // M -> {C, O}, mean 0.5: a tie, C
      0.6,  0.7,   // C -> {M, O}, mean 0.65: M
      1.0,         // M -> {C, O}, one frame (the interval's end): O
  };
  MouthOptions options;
  options.mode = MouthMode::kFollow;
  options.frames_per_shape = 2;
  options.speech = {{0, 19}};
  const MouthResult r = ConvertMouth(m, options, 3);
  EXPECT_EQ(Letters(r.holds), "OMCMOCMCMO");
  EXPECT_EQ(r.holds.back().length, 1);
  // FOLLOW draws nothing: any seed gives the same holds.
  EXPECT_EQ(Letters(ConvertMouth(m, options, 99999).holds), "OMCMOCMCMO");
}

TEST(ConvertMouthTest, FollowTracksTheInputOnAGivenLevelRange) {
  // min/max given: closed -1, open 3, mid_ratio 0.25 -> mid 0.
  MouthOptions options;
  options.mode = MouthMode::kFollow;
  options.frames_per_shape = 1;
  options.min = -1.0;
  options.max = 3.0;
  options.mid_ratio = 0.25;
  options.speech = {{0, 6}};
  const MouthResult r = ConvertMouth({2.9, -0.2, 0.4, 1.6, -1.0, 0.1}, options, 3);
  EXPECT_EQ(r.closed, -1.0);
  EXPECT_EQ(r.mid, 0.0);
  EXPECT_EQ(r.open, 3.0);
  EXPECT_EQ(Letters(r.holds), "OMCOCM");  // 0.4: C's 1.4 vs O's 2.6; 1.6: O's 1.4 vs M's 1.6
  EXPECT_THAT(r.values, ElementsAre(3.0, 0.0, -1.0, 3.0, -1.0, 0.0));
}

// Curve: 0 on 0-9, 1 at 10, 0 on 11-13, 1 on 14-19, 0 from 20 on, but 1e-8 at 30 (below
// 1e-6 of the range) and 2e-6 at 35 (above). Changing pairs: (9,10), (10,11), (13,14),
// (19,20), (34,35), (35,36): runs [9, 12), [13, 15), [19, 21), [34, 37).
std::vector<double> Chatter() {
  std::vector<double> m(45, 0.0);
  m[10] = 1.0;
  for (int f = 14; f < 20; ++f) m[f] = 1.0;
  m[30] = 1e-8;
  m[35] = 2e-6;
  return m;
}

TEST(ConvertMouthTest, DetectsSpeechWhereTheCurveChangesAndMergesShortGaps) {
  MouthOptions options;
  options.frames_per_shape = 1;  // no gap is shorter than 1: the runs themselves
  EXPECT_THAT(ConvertMouth(Chatter(), options, 1).speech,
              ElementsAre(FrameInterval{9, 12}, FrameInterval{13, 15}, FrameInterval{19, 21},
                          FrameInterval{34, 37}));
  options.frames_per_shape = 4;  // the gap of 1 is merged, the gap of 4 is not
  EXPECT_THAT(ConvertMouth(Chatter(), options, 1).speech,
              ElementsAre(FrameInterval{9, 15}, FrameInterval{19, 21}, FrameInterval{34, 37}));
  options.frames_per_shape = 5;  // now the gap of 4 too
  EXPECT_THAT(ConvertMouth(Chatter(), options, 1).speech,
              ElementsAre(FrameInterval{9, 21}, FrameInterval{34, 37}));
}

TEST(ConvertMouthTest, ChangesTwoFramesApartFormOneRun) {
  // Pairs (0,1) and (2,3) change, (1,2) does not: frames 0-3 all speak.
  MouthOptions options;
  options.frames_per_shape = 1;
  EXPECT_THAT(ConvertMouth({0.0, 1.0, 1.0, 0.0, 0.0}, options, 1).speech,
              ElementsAre(FrameInterval{0, 4}));
}

TEST(ConvertMouthTest, AConstantOrEmptyCurveHasNoSpeech) {
  const std::vector<double> flat(30, 0.4);
  const MouthResult r = ConvertMouth(flat, MouthOptions(), 1);
  EXPECT_TRUE(r.speech.empty());
  EXPECT_TRUE(r.holds.empty());
  EXPECT_EQ(r.values, flat);
  const MouthResult empty = ConvertMouth({}, MouthOptions(), 1);
  EXPECT_TRUE(empty.values.empty());
  EXPECT_TRUE(empty.holds.empty());
}

TEST(ConvertMouthTest, GivenIntervalsAreUsedAsTheyAre) {
  // A gap of 1 < n = 3 between them, and a flat curve: neither merged nor replaced.
  MouthOptions options;
  options.speech = {{2, 5}, {6, 10}};
  const std::vector<double> m(12, 0.3);
  const MouthResult r = ConvertMouth(m, options, 5);
  EXPECT_EQ(r.speech, options.speech);
  ASSERT_EQ(r.holds.size(), 3u);
  EXPECT_EQ(r.holds[1].begin, 6);
  EXPECT_NE(r.holds[1].shape, MouthShape::kClosed);  // closed again before the second interval
  for (int f : {0, 1, 5, 10, 11}) EXPECT_EQ(r.values[f], 0.3) << f;
}

TEST(ConvertMouthTest, GivenButEmptySpeechIsNoSpeechNotDetection) {
  // What a film grid leaves of given intervals all shorter than a grid frame: nothing. The
  // talking curve is then left as it is, not searched for speech of its own.
  MouthOptions options;
  options.detect_speech = false;
  const std::vector<double> chatter = Chatter();
  const MouthResult r = ConvertMouth(chatter, options, 7);
  EXPECT_TRUE(r.speech.empty());
  EXPECT_TRUE(r.holds.empty());
  EXPECT_EQ(r.values, chatter);
  options.detect_speech = true;  // the default: detected
  EXPECT_FALSE(ConvertMouth(chatter, options, 7).speech.empty());
}

TEST(ConvertMouthTest, RandomPicksEachAllowedShapeHalfTheTime) {
  MouthOptions options;
  options.frames_per_shape = 1;
  options.speech = {{0, 20000}};
  const MouthResult r = ConvertMouth(std::vector<double>(20000, 0.0), options, 42);
  // Index 1 is the more open of the two shapes other than the previous one.
  int index1 = 0;
  for (size_t i = 1; i < r.holds.size(); ++i) {
    const MouthShape p = r.holds[i - 1].shape;
    const MouthShape s = r.holds[i].shape;
    index1 += p == MouthShape::kOpen ? s == MouthShape::kMid : s == MouthShape::kOpen;
  }
  EXPECT_NEAR(index1 / 19999.0, 0.5, 0.02);  // 0.02 is ~5.7 standard deviations
}

TEST(ConvertMouthTest, SameSeedSameResultDifferentSeedsDifferentSequences) {
  const std::vector<double> m = Talking(3);
  const MouthResult a = ConvertMouth(m, MouthOptions(), 123);
  const MouthResult b = ConvertMouth(m, MouthOptions(), 123);
  EXPECT_EQ(a.values, b.values);
  EXPECT_EQ(Letters(a.holds), Letters(b.holds));
  std::set<std::string> sequences;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    sequences.insert(Letters(ConvertMouth(m, MouthOptions(), seed).holds));
  }
  EXPECT_EQ(sequences.size(), 20u);  // 96 holds: a collision has probability ~2^-90
}

// The exact RANDOM draws: SplitMix64(2019), one top bit per hold in time order, index into the
// two allowed shapes (more closed first). Any machine, compiler or standard library that
// draws differently fails here. Computed independently of koma (a 10-line Python SplitMix64).
TEST(ConvertMouthTest, GoldenRandomSequenceForSeed2019) {
  MouthOptions options;  // n = 3
  options.speech = {{0, 60}, {70, 130}};
  const MouthResult r = ConvertMouth(std::vector<double>(140, 0.0), options, 2019);
  ASSERT_EQ(r.holds.size(), 40u);
  EXPECT_EQ(Letters(r.holds),
            "MCOMCOCMOCMOMCMOCMOC"    // [0, 60)
            "OMOMOMCOCOCMCOMCOCMC");  // [70, 130): closed before it again
}

struct InvalidMouth {
  const char* name;
  void (*mutate)(MouthOptions&);
  const char* message;
};

const InvalidMouth kInvalidMouth[] = {
    {"n zero", [](MouthOptions& o) { o.frames_per_shape = 0; }, "frames_per_shape: 0 must be >= 1"},
    {"n negative", [](MouthOptions& o) { o.frames_per_shape = -3; },
     "frames_per_shape: -3 must be >= 1"},
    {"ratio zero", [](MouthOptions& o) { o.mid_ratio = 0.0; },
     "mid_ratio: 0 must be finite and in (0, 1)"},
    {"ratio one", [](MouthOptions& o) { o.mid_ratio = 1.0; }, "mid_ratio: 1 must be"},
    {"ratio nan", [](MouthOptions& o) { o.mid_ratio = std::nan(""); }, "mid_ratio: nan"},
    {"min inf", [](MouthOptions& o) { o.min = HUGE_VAL; }, "min: inf must be finite"},
    {"max nan", [](MouthOptions& o) { o.max = std::nan(""); }, "max: nan must be finite"},
    {"min equals max",
     [](MouthOptions& o) {
       o.min = 0.5;
       o.max = 0.5;
     },
     "min: 0.5 must be less than max = 0.5"},
    {"min above max",
     [](MouthOptions& o) {
       o.min = 2.0;
       o.max = 1.0;
     },
     "min: 2 must be less than max = 1"},
    {"speech reversed",
     [](MouthOptions& o) {
       o.speech = {{0, 4}, {8, 10}, {40, 38}};
     },
     "speech[2]: [40, 38) is empty or reversed"},
    {"speech empty",
     [](MouthOptions& o) {
       o.speech = {{5, 5}};
     },
     "speech[0]: [5, 5) is empty or reversed"},
    {"speech negative",
     [](MouthOptions& o) {
       o.speech = {{-1, 5}};
     },
     "speech[0]: [-1, 5) is outside [0, 50) (frame_count 50)"},
    {"speech past end",
     [](MouthOptions& o) {
       o.speech = {{10, 20}, {45, 51}};
     },
     "speech[1]: [45, 51) is outside [0, 50)"},
    {"speech overlap",
     [](MouthOptions& o) {
       o.speech = {{10, 20}, {19, 25}};
     },
     "speech[1]: [19, 25) begins before speech[0] = [10, 20) ends (sorted and disjoint)"},
    {"speech unsorted",
     [](MouthOptions& o) {
       o.speech = {{10, 20}, {0, 5}};
     },
     "speech[1]: [0, 5) begins before speech[0]"},
};

TEST(ValidateMouthOptionsTest, RejectsEachBrokenRuleNamingOptionAndValue) {
  MouthOptions valid;
  valid.frames_per_shape = 2;
  valid.mid_ratio = 0.3;
  valid.min = 0.0;
  valid.max = 1.0;
  valid.speech = {{0, 10}, {10, 20}, {30, 50}};  // touching intervals are disjoint
  ASSERT_THAT(ValidateMouthOptions(valid, 50), IsOk());
  ASSERT_THAT(ValidateMouthOptions(MouthOptions(), 0), IsOk());
  for (const InvalidMouth& c : kInvalidMouth) {
    MouthOptions options = valid;
    c.mutate(options);
    EXPECT_THAT(ValidateMouthOptions(options, 50),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.name;
  }
}

TEST(ValidateMouthOptionsTest, OneLevelAloneNeedsOnlyBeFinite) {
  MouthOptions options;
  options.min = 5.0;  // above the curve's maximum, perhaps: the caller's choice
  EXPECT_THAT(ValidateMouthOptions(options, 10), IsOk());
  options.min.reset();
  options.max = -5.0;
  EXPECT_THAT(ValidateMouthOptions(options, 10), IsOk());
}

}  // namespace
}  // namespace koma

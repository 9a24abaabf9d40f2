// ConvertEyes (docs/semantics.md, "LipBlink", paper section 3.2.2, Eq. 5-7): hand-built blinks for
// each hold k, the anime shape (open snaps to closed; closed, half, open), long closures, the
// clip's edges, linked and unlinked eyes, random curves' invariants, and the options'
// validation. Auto-blink: lip_blink_auto_test.cc.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"
#include "tests/core/lip_blink_test_util.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// One eye drawn from letters, levels 0 and 1 given (mid 0.5): the output as letters.
std::string Drawn(const std::string& eye, EyeOptions options = LetterOptions()) {
  const std::vector<double> values = Eye(eye);
  return Letters(ConvertEyes({values}, options, 1).values[0]);
}

std::vector<Blink> BlinksOf(const std::string& eye, EyeOptions options = LetterOptions()) {
  const std::vector<double> values = Eye(eye);
  return ConvertEyes({values}, options, 1).blinks[0];
}

struct HandBuilt {
  const char* input;
  const char* drawn;
  Blink blink;  // the only one
};

// {closing_begin, C_start, C_end, O_span, k, automatic}; O_total = C_end - C_start + O_span.
const HandBuilt kHandBuilt[] = {
    {"OOhCChhOOOO", "OOOCCmOOOOO", {2, 3, 4, 2, 1, false}},      // O_total 3: k 1
    {"OOhCChhhOOO", "OOOCCmmOOOO", {2, 3, 4, 3, 2, false}},      // 4: k 2
    {"OOhCChhhhOOO", "OOOCCmmOOOOO", {2, 3, 4, 4, 2, false}},    // 5: k 2
    {"OOhCChhhhhOOO", "OOOCCCmmmOOOO", {2, 3, 4, 5, 3, false}},  // 6: k 3, closed 3
    {"OqhCCCChhhhOO", "OOOCCCCmmmOOO", {1, 3, 6, 4, 3, false}},  // 7: k 3
    {"OOhChhhhhhOOO", "OOOCCCmmmOOOO", {2, 3, 3, 6, 3, false}},  // 6, one closed frame: 3
    {"OOOCOOO", "OOOCmOO", {3, 3, 3, 0, 1, false}},              // straight in and out
    {"hhCCOOO", "OOCCmOO", {0, 2, 3, 0, 1, false}},              // closing from frame 0
    {"CChOOO", "CCmOOO", {0, 0, 1, 1, 1, false}},                // the clip starts shut
    {"OOOOhCC", "OOOOOCC", {4, 5, 6, 0, 1, false}},              // cut by the clip end
    {"OOOChhhhhh", "OOOCCCmmmO", {3, 3, 3, 6, 3, false}},        // O_span to the end
    {"oohCChhoo", "ooOCCmOoo", {2, 3, 4, 2, 1, false}},          // open noise kept
};

TEST(ConvertEyesTest, HandBuiltBlinksFollowEquationSevenAndTheAnimeShape) {
  for (const HandBuilt& c : kHandBuilt) {
    EXPECT_EQ(Drawn(c.input), c.drawn) << c.input;
    const std::vector<Blink> blinks = BlinksOf(c.input);
    ASSERT_EQ(blinks.size(), 1u) << c.input;
    EXPECT_EQ(blinks[0], c.blink) << c.input;
  }
}

TEST(ConvertEyesTest, LongClosuresStayClosed) {
  // 15 closed frames, O_total 14 + 1: k = 3, and the half-open frames outlast the input's.
  const std::string input = "OOh" + std::string(15, 'C') + "hOOO";
  EXPECT_EQ(Drawn(input), "OOO" + std::string(15, 'C') + "mmmO");
}

TEST(ConvertEyesTest, ClosedRunsWithNoOpenFrameBetweenAreTwoBlinks) {
  // The frames between belong to the first blink's opening span; the second has no closing
  // phase, so both keep closed -> half.
  EXPECT_EQ(Drawn("OOhCChhCCOOO"), "OOOCCmOCCmOO");
  const std::vector<Blink> blinks = BlinksOf("OOhCChhCCOOO");
  ASSERT_EQ(blinks.size(), 2u);
  EXPECT_EQ(blinks[0], (Blink{2, 3, 4, 2, 1, false}));
  EXPECT_EQ(blinks[1], (Blink{7, 7, 8, 0, 1, false}));
}

TEST(ConvertEyesTest, ABlinkNeverRunsIntoTheNextOne) {
  // Closed 3-7 (k 2) then one open frame: its half-open drawing is cut to that frame, so the
  // next blink keeps its frames; its own half-open frame ends the clip's painting.
  EXPECT_EQ(Drawn("OOhCCCCCOCOO"), "OOOCCCCCmCmO");
  EXPECT_EQ(Drawn("OOhCCCCCOCOO").size(), 12u);
}

TEST(ConvertEyesTest, ASquintThatNeverClosesIsNotABlink) {
  EXPECT_EQ(Drawn("OOhqhOOqO"), "OOhqhOOqO");
  EXPECT_TRUE(BlinksOf("OOhqhOOqO").empty());
}

TEST(ConvertEyesTest, LevelsDefaultToTheCurvesMinAndMax) {
  const std::vector<double> eye = {0.9, 0.9, 0.5, 0.2, 0.5, 0.9};
  EyeOptions options;
  options.mid_ratio = 0.25;
  const EyeResult r = ConvertEyes({eye}, options, 1);
  EXPECT_EQ(r.closed[0], 0.2);
  EXPECT_EQ(r.open[0], 0.9);
  EXPECT_DOUBLE_EQ(r.mid[0], 0.2 + 0.25 * 0.7);
  EXPECT_EQ(r.values[0][2], 0.9);  // closing phase -> open
  EXPECT_EQ(r.values[0][3], 0.2);
  EXPECT_EQ(r.values[0][4], r.mid[0]);
}

TEST(ConvertEyesTest, AFlatCurveClosesAtZeroUnlessMinIsGiven) {
  const std::vector<double> flat(10, 0.8);
  const EyeResult r = ConvertEyes({flat}, EyeOptions(), 1);
  EXPECT_EQ(r.closed[0], 0.0);
  EXPECT_EQ(r.open[0], 0.8);
  EXPECT_TRUE(r.blinks[0].empty());
  EXPECT_EQ(r.values[0], flat);
  EyeOptions options;
  options.min = 0.25;
  EXPECT_EQ(ConvertEyes({flat}, options, 1).closed[0], 0.25);
}

// Left 0..1 closing at frame 5; right 0.1..0.8 closing one frame later. Their normalised mean
// is closed (<= 0.1) on 6-7 only, open again at 11: O_span 3 (8-10), O_total 4, k 2.
TEST(ConvertEyesTest, LinkedEyesBlinkOnTheSameFramesEachAtItsOwnLevels) {
  const std::vector<double> left = Eye("OOOOhCCChhOOOOOO");
  std::vector<double> right = Eye("OOOOOhCCChhOOOOO");
  for (double& v : right) v = 0.1 + 0.7 * v;
  const EyeResult r = ConvertEyes({left, right}, EyeOptions(), 1);
  ASSERT_EQ(r.blinks.size(), 2u);
  ASSERT_EQ(r.blinks[0].size(), 1u);
  EXPECT_EQ(r.blinks[0][0], (Blink{4, 6, 7, 3, 2, false}));
  EXPECT_EQ(r.blinks[1], r.blinks[0]);
  EXPECT_EQ(Letters(r.values[0]), "OOOOOOCCmmOOOOOO");
  EXPECT_EQ(r.closed[1], 0.1 + 0.7 * 0.0);
  EXPECT_EQ(r.open[1], 0.1 + 0.7 * 1.0);
  std::vector<double> right_drawn = Eye("OOOOOOCCmmOOOOOO");
  for (double& v : right_drawn) v = 0.1 + 0.7 * v;
  for (size_t f = 0; f < right.size(); ++f) EXPECT_DOUBLE_EQ(r.values[1][f], right_drawn[f]) << f;
}

// The flicker of samples/talk_blink.motion3.json on the 24 fps grid: the left eye starts
// closing one frame before the right (0.85 at frame 3, below its own open level 0.9) while
// their mean (0.925) is still open, so the blink found on the mean closed from frame 4 and
// the left eye's 0.85 passed through: 1, 1, 1, 0.85, 1, 0 (open, half, open, shut). With
// linked eyes every eye's closing phase is repainted open: the blink's closing phase starts
// where the first eye's does.
TEST(ConvertEyesTest, LinkedEyesStayOpenUntilTheSnapWhenOneStartsClosingFirst) {
  const std::vector<double> left = {1, 1, 1, 0.85, 0.5, 0, 0, 0.5, 1, 1, 1};
  const std::vector<double> right = {1, 1, 1, 1, 0.7, 0, 0, 0.5, 1, 1, 1};
  const EyeResult r = ConvertEyes({left, right}, LetterOptions(), 1);
  ASSERT_EQ(r.blinks[0].size(), 1u);
  EXPECT_EQ(r.blinks[0][0], (Blink{3, 5, 6, 1, 1, false}));
  EXPECT_EQ(r.values[0], (std::vector<double>{1, 1, 1, 1, 1, 0, 0, 0.5, 1, 1, 1}));
  EXPECT_EQ(r.values[1], (std::vector<double>{1, 1, 1, 1, 1, 0, 0, 0.5, 1, 1, 1}));
  // The same with the eyes swapped: the right eye's early start counts the same way.
  const EyeResult swapped = ConvertEyes({right, left}, LetterOptions(), 1);
  EXPECT_EQ(swapped.blinks[0], r.blinks[0]);
  EXPECT_EQ(swapped.values[1], r.values[0]);
}

// The earlier start never reaches back into the previous blink's repaint: between two blinks
// the left eye never reopens (0.85) while the mean does, so the second blink's closing phase
// stops where the first blink's half-open frame ends.
TEST(ConvertEyesTest, AnEarlyClosingPhaseStopsAtThePreviousBlink) {
  const std::vector<double> left = {1, 0, 0, 0.85, 0.85, 0.85, 0.85, 0, 0, 1, 1};
  const std::vector<double> right = {1, 0, 0, 1, 1, 1, 1, 0, 0, 1, 1};
  const EyeResult r = ConvertEyes({left, right}, LetterOptions(), 1);
  ASSERT_EQ(r.blinks[0].size(), 2u);
  EXPECT_EQ(r.blinks[0][0], (Blink{1, 1, 2, 0, 1, false}));
  EXPECT_EQ(r.blinks[0][1].closing_begin, 4);  // the mean alone: 7
  EXPECT_EQ(r.values[0], (std::vector<double>{1, 0, 0, 0.5, 1, 1, 1, 0, 0, 0.5, 1}));
}

TEST(ConvertEyesTest, AFlatCurveTakesNoPartInLinkedDetectionButIsPainted) {
  // Only the left eye is animated; the right one stays at 0.8 (closed level 0, as it is flat).
  const std::vector<double> left = Eye("OOOOhCCChhOOOOOO");
  const std::vector<double> right(left.size(), 0.8);
  const EyeResult r = ConvertEyes({left, right}, EyeOptions(), 1);
  ASSERT_EQ(r.blinks[1].size(), 1u);
  EXPECT_EQ(r.blinks[1][0], (Blink{4, 5, 7, 2, 2, false}));
  EXPECT_EQ(Letters(r.values[0]), "OOOOOCCCmmOOOOOO");
  const std::vector<double> painted = {0.8, 0.8, 0.8, 0.8, 0.8, 0.0, 0.0, 0.0,
                                       0.4, 0.4, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8};
  EXPECT_EQ(r.values[1], painted);
}

TEST(ConvertEyesTest, UnlinkedEyesBlinkEachOnItsOwn) {
  const std::vector<double> left = Eye("OOOOhCCChhOOOOOO");
  std::vector<double> right = Eye("OOOOOhCCChhOOOOO");
  for (double& v : right) v = 0.1 + 0.7 * v;
  EyeOptions options;
  options.linked = false;
  const EyeResult r = ConvertEyes({left, right}, options, 1);
  ASSERT_EQ(r.blinks[0].size(), 1u);
  ASSERT_EQ(r.blinks[1].size(), 1u);
  EXPECT_EQ(r.blinks[0][0], (Blink{4, 5, 7, 2, 2, false}));
  EXPECT_EQ(r.blinks[1][0], (Blink{5, 6, 8, 2, 2, false}));
  EXPECT_EQ(Letters(r.values[0]), "OOOOOCCCmmOOOOOO");
}

TEST(ConvertEyesTest, NoCurvesNoResult) {
  const EyeResult r = ConvertEyes({}, EyeOptions(), 1);
  EXPECT_TRUE(r.values.empty());
  EXPECT_TRUE(r.blinks.empty());
}

// Random eyes (blinks of every shape, squints, open noise): every detected blink matches the
// generated closed run and Eq. 7, and is drawn open -> closed (>= k) -> k half -> open within
// its span, cut only by the clip and the next blink (never, when open stretches of >= 3
// frames separate them); everything else is the input. A single curve gives the same blinks
// linked (normalised) or not.
TEST(ConvertEyesTest, RandomEyesKeepEveryInvariant) {
  for (int min_open : {1, 3}) {
    for (uint64_t trial = 0; trial < 300; ++trial) {
      SplitMix64 rng(trial);
      const RandomEye eye = MakeRandomEye(rng, 40 + rng.Int(0, 400), min_open);
      const EyeResult r = ConvertEyes({eye.values}, LetterOptions(), trial);
      EyeOptions unlinked = LetterOptions();
      unlinked.linked = false;
      ASSERT_EQ(ConvertEyes({eye.values}, unlinked, trial).blinks[0], r.blinks[0]);
      const std::vector<Blink>& blinks = r.blinks[0];
      ASSERT_EQ(blinks.size(), eye.closed.size()) << "trial " << trial;
      for (size_t i = 0; i < blinks.size(); ++i) {
        EXPECT_EQ(blinks[i].closed_begin, eye.closed[i].begin) << "trial " << trial;
        EXPECT_EQ(blinks[i].closed_end, eye.closed[i].end - 1) << "trial " << trial;
        const int o_total = blinks[i].closed_end - blinks[i].closed_begin + blinks[i].open_span;
        EXPECT_EQ(blinks[i].hold, o_total <= 3 ? 1 : o_total <= 5 ? 2 : 3);
      }
      ExpectAnimeBlinks(eye.values, r.values[0], blinks, {0.0, 0.5, 1.0}, min_open >= 3);
    }
  }
}

struct InvalidEyes {
  const char* name;
  void (*mutate)(EyeOptions&);
  const char* message;
};

const InvalidEyes kInvalidEyes[] = {
    {"ratio zero", [](EyeOptions& o) { o.mid_ratio = 0.0; },
     "mid_ratio: 0 must be finite and in (0, 1)"},
    {"ratio inf", [](EyeOptions& o) { o.mid_ratio = HUGE_VAL; }, "mid_ratio: inf"},
    {"threshold zero", [](EyeOptions& o) { o.threshold = 0.0; },
     "threshold: 0 must be finite and in (0, 0.5)"},
    {"threshold half", [](EyeOptions& o) { o.threshold = 0.5; }, "threshold: 0.5 must be"},
    {"threshold nan", [](EyeOptions& o) { o.threshold = std::nan(""); }, "threshold: nan"},
    {"min nan", [](EyeOptions& o) { o.min = std::nan(""); }, "min: nan must be finite"},
    {"max inf", [](EyeOptions& o) { o.max = -HUGE_VAL; }, "max: -inf must be finite"},
    {"min above max",
     [](EyeOptions& o) {
       o.min = 1.0;
       o.max = 0.0;
     },
     "min: 1 must be less than max = 0"},
    {"fps zero", [](EyeOptions& o) { o.fps = 0.0; }, "fps: 0 must be finite and > 0"},
    {"fps nan", [](EyeOptions& o) { o.fps = std::nan(""); }, "fps: nan"},
    {"mean zero", [](EyeOptions& o) { o.auto_blink.mean_interval_s = 0.0; },
     "auto_blink.mean_interval_s: 0 must be finite and > 0"},
    {"mean inf", [](EyeOptions& o) { o.auto_blink.mean_interval_s = HUGE_VAL; },
     "auto_blink.mean_interval_s: inf"},
    {"spread negative", [](EyeOptions& o) { o.auto_blink.spread_s = -0.5; },
     "auto_blink.spread_s: -0.5 must be finite, >= 0 and < auto_blink.mean_interval_s = 4"},
    {"spread equals mean", [](EyeOptions& o) { o.auto_blink.spread_s = 4.0; },
     "auto_blink.spread_s: 4 must be"},
    {"hold zero", [](EyeOptions& o) { o.auto_blink.hold = 0; },
     "auto_blink.hold: 0 must be in [1, 3]"},
    {"hold four", [](EyeOptions& o) { o.auto_blink.hold = 4; }, "auto_blink.hold: 4 must be"},
    {"keep reversed",
     [](EyeOptions& o) {
       o.auto_blink.keep = {{10, 2}};
     },
     "auto_blink.keep[0]: [10, 2) is empty or reversed"},
    {"keep past end",
     [](EyeOptions& o) {
       o.auto_blink.keep = {{0, 2}, {90, 101}};
     },
     "auto_blink.keep[1]: [90, 101) is outside [0, 100) (frame_count 100)"},
    {"keep overlap",
     [](EyeOptions& o) {
       o.auto_blink.keep = {{0, 20}, {10, 30}};
     },
     "auto_blink.keep[1]: [10, 30) begins before auto_blink.keep[0] = [0, 20) ends"},
};

TEST(ValidateEyeOptionsTest, RejectsEachBrokenRuleNamingOptionAndValue) {
  EyeOptions valid;
  valid.min = 0.0;
  valid.max = 1.0;
  valid.auto_blink.enabled = true;
  valid.auto_blink.keep = {{0, 20}, {20, 40}, {99, 100}};
  ASSERT_THAT(ValidateEyeOptions(valid, 100), IsOk());
  ASSERT_THAT(ValidateEyeOptions(EyeOptions(), 0), IsOk());
  for (const InvalidEyes& c : kInvalidEyes) {
    EyeOptions options = valid;
    c.mutate(options);
    EXPECT_THAT(ValidateEyeOptions(options, 100),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.name;
    options.auto_blink.enabled = false;  // checked whether used or not
    EXPECT_FALSE(ValidateEyeOptions(options, 100).ok()) << c.name;
  }
}

}  // namespace
}  // namespace koma

// ConvertEyes (docs/semantics.md, "LipBlink", paper section 3.2.2, Eq. 5-7): hand-built blinks for
// each hold k, the anime shape (open snaps to closed; closed, half, open), long closures, the
// clip's edges, linked and unlinked eyes, random curves' invariants, and the options'
// validation. Auto-blink: lip_blink_auto_test.cc.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
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

constexpr int kHeld = 4;  // lip_blink_internal::kHeldFrames

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

// Open levels (docs/semantics.md, "LipBlink", "Open levels"): with E_max unset, a blink's
// open drawing is the input's own level either side of it, not the curve's maximum.

// A frame-by-frame expectation: the input, each blink painted with its own levels (closing
// phase at `before`, closed, k frames half between closed and `after`, then `after`).
std::vector<double> PaintedWith(const std::vector<double>& input, const std::vector<Blink>& blinks,
                                const std::vector<BlinkLevels>& levels, double closed) {
  std::vector<double> expected = input;
  const int frame_count = static_cast<int>(input.size());
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    const int end = SpanEnd(blinks, i, frame_count);
    const auto paint = [&](int from, int to, double level) {
      for (int f = from; f < std::min(to, end); ++f) expected[f] = level;
    };
    const int closed_stop = std::max(b.closed_end, b.closed_begin + b.hold - 1) + 1;
    paint(b.closing_begin, b.closed_begin, levels[i].before);
    paint(b.closed_begin, closed_stop, closed);
    paint(closed_stop, closed_stop + b.hold, closed + 0.5 * (levels[i].after - closed));
    paint(closed_stop + b.hold, end, levels[i].after);
  }
  return expected;
}

std::vector<double> Repeat(double value, int frames) {
  return std::vector<double>(static_cast<size_t>(frames), value);
}

std::vector<double> Joined(std::initializer_list<std::vector<double>> parts) {
  std::vector<double> all;
  for (const std::vector<double>& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

// Open at 1, a squint held at 0.8 with a blink inside it (closed at frames 23-24), open again.
std::vector<double> SquintWithABlink() {
  return Joined({Repeat(1.0, 10), {0.9}, Repeat(0.8, 10), {0.5, 0.2}, Repeat(0.0, 2), {0.3, 0.6},
                 Repeat(0.8, 10), {0.9}, Repeat(1.0, 10)});
}

// Open at 1, then a squint held at 0.8 with a blink inside it, then open again: the blink
// snaps shut from 0.8, its half-open drawing is 0.4 and it reopens to 0.8. Before, E_max (1)
// was the open drawing, and since 0.8 never counted as open the whole squint around the blink
// was painted at 1 (the squint erased).
TEST(ConvertEyesTest, AHeldSquintReopensToItsOwnLevel) {
  const std::vector<double> eye = SquintWithABlink();
  const EyeResult r = ConvertEyes({eye}, EyeOptions(), 1);
  ASSERT_EQ(r.blinks[0].size(), 1u);
  EXPECT_EQ(r.blinks[0][0], (Blink{21, 23, 24, 2, 1, false}));  // O_total 1 + 2: k 1
  ASSERT_EQ(r.levels[0].size(), 1u);
  EXPECT_EQ(r.levels[0][0].before, 0.8);
  EXPECT_EQ(r.levels[0][0].after, 0.8);
  EXPECT_EQ(r.open[0], 1.0);  // E_max still scales delta
  std::vector<double> expected = eye;
  expected[21] = expected[22] = 0.8;  // the closing phase snaps shut from 0.8
  expected[25] = 0.4;                 // half of 0.8
  expected[26] = 0.8;                 // and open at 0.8
  EXPECT_EQ(r.values[0], expected);
  // A curve held at 0.8 throughout reopens to 0.8 as well.
  const std::vector<double> held =
      Joined({Repeat(0.8, 8), {0.4}, Repeat(0.0, 2), {0.2, 0.5}, Repeat(0.8, 8)});
  const EyeResult h = ConvertEyes({held}, EyeOptions(), 1);
  ASSERT_EQ(h.blinks[0].size(), 1u);
  EXPECT_EQ(h.values[0],
            (Joined({Repeat(0.8, 8), {0.8}, Repeat(0.0, 2), {0.4, 0.8}, Repeat(0.8, 8)})));
}

// E_max given: every open drawing is E_max, as the paper (the squint above painted at 1).
TEST(ConvertEyesTest, AGivenMaxIsEveryOpenDrawing) {
  const std::vector<double> eye = SquintWithABlink();
  EyeOptions options;
  options.max = 1.0;
  const EyeResult r = ConvertEyes({eye}, options, 1);
  ASSERT_EQ(r.blinks[0].size(), 1u);
  EXPECT_EQ(r.blinks[0][0].closing_begin, 11);  // back to the last frame at or above 0.9
  EXPECT_EQ(r.levels[0][0].before, 1.0);
  EXPECT_EQ(r.levels[0][0].after, 1.0);
  for (int f = 11; f < 23; ++f) EXPECT_EQ(r.values[0][f], 1.0) << f;
}

// Haru's m04 (issue 40): the eyes keyed at 1 between blinks, with a brief 1.2 overshoot. E_max
// is 1.2, so before, 1 never counted as open: every closing phase reached back to the previous
// blink or frame 0 and every opening span ran to the next one, all painted 1.2 (wide-eyed the
// whole clip). Now the eyes are drawn at 1 between blinks, both linked eyes keyed a little
// differently (the right at 0.97, closing a frame later) each at its own level; only the
// overshoot's own frames show 1.2, as keyed.
TEST(ConvertEyesTest, AnOvershootDoesNotOpenTheEyesWide) {
  const std::vector<double> blink = {0.6, 0.0, 0.0, 0.5};
  const std::vector<double> left = Joined({Repeat(1.0, 12),
                                           blink,
                                           Repeat(1.0, 10),
                                           {1.1, 1.2, 1.1},
                                           Repeat(1.0, 10),
                                           blink,
                                           Repeat(1.0, 12)});
  std::vector<double> right = Joined({Repeat(1.0, 13),
                                      blink,
                                      Repeat(1.0, 9),
                                      {1.1, 1.2, 1.1},
                                      Repeat(1.0, 10),
                                      blink,
                                      Repeat(1.0, 12)});
  right.pop_back();
  right.insert(right.begin() + 53, 1.0);  // the second blink a frame later too
  for (double& v : right) v *= 0.97;
  ASSERT_EQ(left.size(), right.size());
  for (const bool linked : {true, false}) {
    EyeOptions options;
    options.linked = linked;
    const EyeResult r = ConvertEyes({left, right}, options, 1);
    for (size_t c = 0; c < 2; ++c) {
      const std::vector<double>& input = c == 0 ? left : right;
      const double level = c == 0 ? 1.0 : 0.97;
      EXPECT_EQ(r.open[c], 1.2 * level) << c;  // E_max: the overshoot
      ASSERT_EQ(r.blinks[c].size(), 2u) << "linked " << linked << " curve " << c;
      for (const BlinkLevels& l : r.levels[c]) {
        EXPECT_EQ(l.before, level);
        EXPECT_EQ(l.after, level);
      }
      EXPECT_EQ(r.values[c], PaintedWith(input, r.blinks[c], r.levels[c], 0.0)) << c;
      // Outside the blinks' repaints every frame is the input: 1 (0.97), but the overshoot.
      const std::vector<bool> painted = [&] {
        std::vector<bool> p(input.size(), false);
        for (size_t i = 0; i < r.blinks[c].size(); ++i) {
          for (int f = r.blinks[c][i].closing_begin;
               f < SpanEnd(r.blinks[c], i, static_cast<int>(input.size())); ++f) {
            p[f] = true;
          }
        }
        return p;
      }();
      int wide = 0;
      for (size_t f = 0; f < input.size(); ++f) {
        if (painted[f]) {
          EXPECT_LE(r.values[c][f], level) << f;
        } else {
          EXPECT_EQ(r.values[c][f], input[f]) << f;
          wide += r.values[c][f] > level;
        }
      }
      EXPECT_EQ(wide, 3) << c;  // 1.1, 1.2, 1.1: the overshoot as keyed, nothing more
    }
  }
}

// An eye that reopens into its overshoot (0 -> 1.2 -> 1): the open drawing after the blink is
// the top it opens to, so the repaint joins the input there without a dip, and the eye then
// settles to 1 as keyed; the next blink closes from 1.
TEST(ConvertEyesTest, AnEyeThatOpensIntoAnOvershootReopensToItsTop) {
  const std::vector<double> eye = Joined({Repeat(1.0, 8),
                                          {0.5},
                                          Repeat(0.0, 2),
                                          {0.6},
                                          {1.2, 1.15, 1.05},
                                          Repeat(1.0, 10),
                                          {0.5},
                                          Repeat(0.0, 2),
                                          {0.5},
                                          Repeat(1.0, 6)});
  const EyeResult r = ConvertEyes({eye}, EyeOptions(), 1);
  ASSERT_EQ(r.blinks[0].size(), 2u);
  EXPECT_EQ(r.levels[0][0].before, 1.0);
  EXPECT_EQ(r.levels[0][0].after, 1.2);
  EXPECT_EQ(r.levels[0][1].before, 1.0);
  EXPECT_EQ(r.levels[0][1].after, 1.0);
  EXPECT_EQ(r.values[0], PaintedWith(eye, r.blinks[0], r.levels[0], 0.0));
  EXPECT_EQ(r.values[0][11], 0.6);  // the half-open drawing: half of 1.2
  EXPECT_EQ(r.values[0][12], 1.2);  // then the input: the overshoot, settling to 1
  EXPECT_EQ(r.values[0][15], 1.0);
}

// A frame that only passes between two closings (a double blink) is not a level: both sides
// read against the level the eye was open at, as the paper reads them against E_max, so the
// frames between are the first blink's opening span and the second has no closing phase.
TEST(ConvertEyesTest, AHalfOpenFrameBetweenTwoClosingsIsNotALevel) {
  const std::vector<double> eye = Eye("OOOOhCChhCCOOOO");
  const EyeResult r = ConvertEyes({eye}, EyeOptions(), 1);
  ASSERT_EQ(r.blinks[0].size(), 2u);
  EXPECT_EQ(r.blinks[0][0], (Blink{4, 5, 6, 2, 1, false}));
  EXPECT_EQ(r.blinks[0][1], (Blink{9, 9, 10, 0, 1, false}));
  EXPECT_EQ(r.levels[0][0].after, 1.0);
  EXPECT_EQ(r.levels[0][1].before, 1.0);
  EXPECT_EQ(Letters(r.values[0]), "OOOOOCCmOCCmOOO");
  EXPECT_EQ(Letters(r.values[0]), Drawn("OOOOhCChhCCOOOO"));  // the same as with E_max given
}

// Random eyes whose open stretches are each held at a level of their own in [0.55, 1.25], some
// with a brief overshoot inside, separated by blinks with strictly monotone closing and opening
// ramps: every blink closes from the level before it and reopens to the level after it, with
// the closing phase and opening span the ramps, and every other frame is the input. Linked
// with a second eye keyed at 0.9 of the first, each eye at its own levels.
TEST(ConvertEyesTest, RandomHeldLevelsAreEachBlinksOpenDrawings) {
  for (uint64_t trial = 0; trial < 300; ++trial) {
    SplitMix64 rng(trial);
    std::vector<double> eye;
    std::vector<double> stretch_levels;
    struct Expected {
      int closing_begin, closed_begin, closed_end, open_span;
    };
    std::vector<Expected> expected;
    const auto level = [&] { return 0.55 + 0.7 * rng.Unit(); };
    const auto hold_at = [&](double l) {
      const int n = rng.Int(8, 30);
      const int overshoot_at =
          n >= 2 * kHeld + 4 && rng.OneIn(2) ? rng.Int(kHeld, n - kHeld - 3) : -1;
      for (int i = 0; i < n; ++i) {
        const bool over = overshoot_at >= 0 && i >= overshoot_at && i < overshoot_at + 3;
        eye.push_back(over ? l + 0.05 + 0.2 * rng.Unit() : l);
      }
      stretch_levels.push_back(l);
    };
    // A ramp of `n` values strictly between 0.3 and 0.85 of the way to `l`, rising or falling:
    // never closed (at most 0.1 of a range below 1.5) nor open at `l` (0.9 l).
    const auto ramp = [&](double l, int n, bool rising) {
      std::vector<double> r;
      for (int i = 0; i < n; ++i) r.push_back(l * (0.3 + 0.55 * (i + rng.Unit()) / n));
      if (!rising) std::reverse(r.begin(), r.end());
      eye.insert(eye.end(), r.begin(), r.end());
    };
    double l = level();
    hold_at(l);
    for (int blinks = rng.Int(1, 6); blinks > 0; --blinks) {
      Expected e;
      e.closing_begin = static_cast<int>(eye.size());
      ramp(l, rng.Int(0, 3), false);
      e.closed_begin = static_cast<int>(eye.size());
      for (int i = rng.Int(1, 6); i > 0; --i) eye.push_back(i % 2 ? 0.0 : 0.01 * rng.Unit());
      e.closed_end = static_cast<int>(eye.size()) - 1;
      l = level();
      const int opening = rng.Int(0, 6);
      ramp(l, opening, true);
      e.open_span = opening;
      hold_at(l);
      expected.push_back(e);
    }
    std::vector<double> right = eye;
    for (double& v : right) v *= 0.9;
    for (const bool linked : {true, false}) {
      EyeOptions options;
      options.linked = linked;
      const EyeResult r = ConvertEyes({eye, right}, options, trial);
      for (size_t c = 0; c < 2; ++c) {
        const double scale = c == 0 ? 1.0 : 0.9;
        const std::vector<double>& input = c == 0 ? eye : right;
        const std::vector<Blink>& blinks = r.blinks[c];
        ASSERT_EQ(blinks.size(), expected.size()) << "trial " << trial;
        for (size_t i = 0; i < blinks.size(); ++i) {
          const Expected& e = expected[i];
          EXPECT_EQ(blinks[i].closing_begin, e.closing_begin)
              << "trial " << trial << " blink " << i;
          EXPECT_EQ(blinks[i].closed_begin, e.closed_begin) << "trial " << trial;
          EXPECT_EQ(blinks[i].closed_end, e.closed_end) << "trial " << trial;
          EXPECT_EQ(blinks[i].open_span, e.open_span) << "trial " << trial << " blink " << i;
          EXPECT_EQ(r.levels[c][i].before, stretch_levels[i] * scale) << "trial " << trial;
          EXPECT_EQ(r.levels[c][i].after, stretch_levels[i + 1] * scale) << "trial " << trial;
        }
        ASSERT_EQ(r.values[c], PaintedWith(input, blinks, r.levels[c], 0.0)) << "trial " << trial;
      }
    }
  }
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

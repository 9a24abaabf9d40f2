// Curve evaluation (motion3.json's rules) on hand-computed values, the boundary rules, dense
// curves, the cursor's agreement with EvaluateCurve, and every validation rule of curves.h.
#include "core/curves.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/curve_cursor.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

constexpr bool kRestricted = true;
constexpr bool kUnrestricted = false;

CurveSegment Seg(SegmentType type, double frame, double value) {
  CurveSegment segment;
  segment.type = type;
  segment.end = {frame, value};
  return segment;
}
CurveSegment Linear(double frame, double value) { return Seg(SegmentType::kLinear, frame, value); }
CurveSegment Stepped(double frame, double value) {
  return Seg(SegmentType::kStepped, frame, value);
}
CurveSegment InverseStepped(double frame, double value) {
  return Seg(SegmentType::kInverseStepped, frame, value);
}
CurveSegment Bezier(CurvePoint p1, CurvePoint p2, CurvePoint p3) {
  CurveSegment segment = Seg(SegmentType::kBezier, p3.frame, p3.value);
  segment.handles[0] = p1;
  segment.handles[1] = p2;
  return segment;
}

Curve Keyframes(CurvePoint start, std::vector<CurveSegment> segments, std::string id = "P") {
  Curve curve;
  curve.id = std::move(id);
  curve.start = start;
  curve.segments = std::move(segments);
  return curve;
}

TEST(EvaluateCurveTest, LinearInterpolatesAndHoldsTheEnds) {
  const Curve curve = Keyframes({0, 0}, {Linear(10, 5)});
  EXPECT_EQ(EvaluateCurve(curve, 4.0, kRestricted), 2.0);
  EXPECT_EQ(EvaluateCurve(curve, 0.0, kRestricted), 0.0);
  EXPECT_EQ(EvaluateCurve(curve, -3.0, kRestricted), 0.0);  // before the first point
  EXPECT_EQ(EvaluateCurve(curve, 10.0, kRestricted), 5.0);  // at the last point
  EXPECT_EQ(EvaluateCurve(curve, 99.0, kRestricted), 5.0);  // after it
}

TEST(EvaluateCurveTest, SteppedShowsThePreviousValueUntilItsEnd) {
  const Curve curve = Keyframes({0, 1}, {Stepped(10, 3), Linear(20, 13)});
  EXPECT_EQ(EvaluateCurve(curve, 0.0, kRestricted), 1.0);
  EXPECT_EQ(EvaluateCurve(curve, 9.999, kRestricted), 1.0);
  EXPECT_EQ(EvaluateCurve(curve, 10.0, kRestricted), 3.0);  // the linear segment starts here
  EXPECT_EQ(EvaluateCurve(curve, 15.0, kRestricted), 8.0);
  EXPECT_EQ(EvaluateCurve(curve, -1.0, kRestricted), 1.0);
}

TEST(EvaluateCurveTest, InverseSteppedJumpsRightAfterThePreviousPoint) {
  const Curve curve = Keyframes({0, 1}, {InverseStepped(10, 3)});
  EXPECT_EQ(EvaluateCurve(curve, 0.0, kRestricted), 3.0);  // the point starts the segment
  EXPECT_EQ(EvaluateCurve(curve, 5.0, kRestricted), 3.0);
  EXPECT_EQ(EvaluateCurve(curve, 10.0, kRestricted), 3.0);
  // Our documented choice before the first point: its value (Cubism's runtime gives 3).
  EXPECT_EQ(EvaluateCurve(curve, -0.5, kRestricted), 1.0);
}

TEST(EvaluateCurveTest, APointsTimeBelongsToTheSegmentStartingThere) {
  // At t = 10 the linear segment would give 5; the inverse-stepped one starting there gives 9.
  const Curve curve = Keyframes({0, 0}, {Linear(10, 5), InverseStepped(20, 9)});
  EXPECT_EQ(EvaluateCurve(curve, 10.0, kRestricted), 9.0);
  EXPECT_NEAR(EvaluateCurve(curve, std::nextafter(10.0, 0.0), kRestricted), 5.0, 1e-12);
  const Curve steps = Keyframes({0, 0}, {Stepped(10, 5), Stepped(20, 9)});
  EXPECT_EQ(EvaluateCurve(steps, 10.0, kRestricted), 5.0);
  EXPECT_EQ(EvaluateCurve(steps, 20.0, kRestricted), 9.0);
}

TEST(EvaluateCurveTest, NoSegmentsIsTheStartValueEverywhere) {
  const Curve curve = Keyframes({4, 7}, {});
  EXPECT_EQ(EvaluateCurve(curve, 0.0, kUnrestricted), 7.0);
  EXPECT_EQ(EvaluateCurve(curve, 100.0, kRestricted), 7.0);
}

// Values 0, 0, 1, 1 make the Bezier smoothstep: B(u) = 3u^2 - 2u^3.
TEST(EvaluateCurveTest, RestrictedBezierIsLinearInTimeAndIgnoresHandleTimes) {
  const Curve curve = Keyframes({0, 0}, {Bezier({9, 0}, {9.5, 1}, {10, 1})});
  EXPECT_EQ(EvaluateCurve(curve, 5.0, kRestricted), 0.5);      // u = 0.5
  EXPECT_EQ(EvaluateCurve(curve, 2.5, kRestricted), 0.15625);  // u = 0.25: 3/16 - 2/64
  EXPECT_EQ(EvaluateCurve(curve, 7.5, kRestricted), 0.84375);  // u = 0.75: 27/16 - 54/64
  EXPECT_EQ(EvaluateCurve(curve, -2.0, kRestricted), 0.0);
  EXPECT_EQ(EvaluateCurve(curve, 10.0, kRestricted), 1.0);
}

TEST(EvaluateCurveTest, UnrestrictedBezierWithSymmetricHandlesHitsTheMiddle) {
  // Times 0, 2, 8, 10: x(0.5) = (0 + 3*2 + 3*8 + 10) / 8 = 5, so t = 5 solves to u = 0.5.
  const Curve curve = Keyframes({0, 0}, {Bezier({2, 0}, {8, 1}, {10, 1})});
  EXPECT_NEAR(EvaluateCurve(curve, 5.0, kUnrestricted), 0.5, 1e-12);
  // Its handle times matter: x(u) = 6u + 12u^2 - 8u^3, so t = 2.5 is not u = 0.25.
  EXPECT_GT(std::abs(EvaluateCurve(curve, 2.5, kUnrestricted) - 0.15625), 1e-3);
}

TEST(EvaluateCurveTest, UnrestrictedBezierSolvesSkewedHandles) {
  // Times 0, 0, 0, 8: x(u) = 8u^3. Values 0, 0, 0, 8: y(u) = 8u^3 too, so y = t exactly,
  // while restricted mode (u = t / 8) gives 8 (t / 8)^3.
  const Curve curve = Keyframes({0, 0}, {Bezier({0, 0}, {0, 0}, {8, 8})});
  for (double t : {0.5, 1.0, 2.0, 4.0, 7.0}) {
    EXPECT_NEAR(EvaluateCurve(curve, t, kUnrestricted), t, 1e-12) << "t = " << t;
    EXPECT_DOUBLE_EQ(EvaluateCurve(curve, t, kRestricted), t * t * t / 64.0) << "t = " << t;
  }
  // Times 0, 6, 6, 6: x(u) = 6 (1 - (1 - u)^3); t = 5.25 gives (1 - u)^3 = 1/8, u = 1/2, and
  // values 0, 0, 1, 1 give smoothstep(1/2) = 1/2 (restricted: u = 0.875, 0.95703125).
  const Curve late = Keyframes({0, 0}, {Bezier({6, 0}, {6, 1}, {6, 1})});
  EXPECT_NEAR(EvaluateCurve(late, 5.25, kUnrestricted), 0.5, 1e-12);
  EXPECT_EQ(EvaluateCurve(late, 5.25, kRestricted), 0.95703125);
}

TEST(EvaluateCurveTest, DenseIsLinearBetweenIntegerFramesAndClamped) {
  Curve curve;
  curve.id = "D";
  curve.samples = {0, 10, 4};
  EXPECT_EQ(EvaluateCurve(curve, 0.5, kRestricted), 5.0);
  EXPECT_EQ(EvaluateCurve(curve, 1.0, kRestricted), 10.0);
  EXPECT_EQ(EvaluateCurve(curve, 1.25, kRestricted), 8.5);
  EXPECT_EQ(EvaluateCurve(curve, -1.0, kRestricted), 0.0);
  EXPECT_EQ(EvaluateCurve(curve, 2.0, kRestricted), 4.0);
  EXPECT_EQ(EvaluateCurve(curve, 7.0, kRestricted), 4.0);
}

// A random valid keyframe curve of every segment type, handles inside their spans and in order.
Curve RandomCurve(SplitMix64& rng, int segments) {
  Curve curve = Keyframes({rng.Unit() * 3.0, rng.Unit()}, {});
  double frame = curve.start.frame;
  for (int s = 0; s < segments; ++s) {
    const double from = frame;
    frame += 0.25 + 5.0 * rng.Unit();
    CurveSegment segment = Seg(static_cast<SegmentType>(rng.Int(0, 3)), frame, rng.Unit() * 10);
    const double a = from + (frame - from) * rng.Unit();
    const double b = from + (frame - from) * rng.Unit();
    segment.handles[0] = {std::min(a, b), rng.Unit() * 10};
    segment.handles[1] = {std::max(a, b), rng.Unit() * 10};
    curve.segments.push_back(segment);
  }
  return curve;
}

TEST(CurveCursorTest, AgreesBitForBitWithEvaluateCurveForwardAndBackward) {
  SplitMix64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Curve curve = RandomCurve(rng, rng.Int(0, 12));
    const bool restricted = rng.OneIn(2);
    CurveCursor cursor(curve, restricted);
    double t = -2.0;
    for (int k = 0; k < 300; ++k) {
      // Mostly forward steps, some exactly on keyframes, sometimes a jump back.
      if (rng.OneIn(10) && !curve.segments.empty()) {
        t = curve.segments[rng.Int(0, static_cast<int>(curve.segments.size()) - 1)].end.frame;
      } else if (rng.OneIn(15)) {
        t -= 10.0 * rng.Unit();
      } else {
        t += 0.5 * rng.Unit();
      }
      ASSERT_EQ(cursor.Evaluate(t), EvaluateCurve(curve, t, restricted))
          << "trial " << trial << " t = " << t;
    }
  }
}

TEST(EvaluateCurveTest, UnrestrictedBezierStaysWithinItsControlValues) {
  SplitMix64 rng(11);
  int beziers = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Curve curve = RandomCurve(rng, 1);
    const CurveSegment& s = curve.segments[0];
    if (s.type != SegmentType::kBezier) continue;
    ++beziers;
    const auto [lo, hi] =
        std::minmax({curve.start.value, s.handles[0].value, s.handles[1].value, s.end.value});
    for (int k = 0; k <= 100; ++k) {
      const double t = curve.start.frame + (s.end.frame - curve.start.frame) * k / 100.0;
      const double v = EvaluateCurve(curve, t, kUnrestricted);
      EXPECT_GE(v, lo - 1e-12) << "t = " << t;
      EXPECT_LE(v, hi + 1e-12) << "t = " << t;
    }
  }
  EXPECT_GT(beziers, 20);
}

// Restricted Beziers (Cubism Editor's default), where handle order is checked too.
CurveSet ValidSet() {
  CurveSet set;
  set.frame_count = 3;
  set.beziers_restricted = true;
  set.curves.push_back(Keyframes({0, 0}, {Linear(1, 1), Bezier({1.5, 0}, {2, 1}, {3, 2})}, "A"));
  Curve dense;
  dense.id = "B";
  dense.samples = {0, 1, 2};
  set.curves.push_back(dense);
  return set;
}

TEST(ValidateCurveSetTest, AcceptsAValidSetInBothBezierModes) {
  CurveSet set = ValidSet();
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
  set.beziers_restricted = false;
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
}

struct InvalidCase {
  const char* name;
  void (*mutate)(CurveSet&);
  const char* message;  // a substring of the expected message
};

const InvalidCase kInvalidCases[] = {
    {"fps zero", [](CurveSet& s) { s.fps = 0; }, "fps: 0 must be finite and > 0"},
    {"fps nan", [](CurveSet& s) { s.fps = std::nan(""); }, "fps: nan"},
    {"fps inf", [](CurveSet& s) { s.fps = HUGE_VAL; }, "fps: inf"},
    {"one frame", [](CurveSet& s) { s.frame_count = 1; }, "frame_count: 1 must be >= 2"},
    {"no curves", [](CurveSet& s) { s.curves.clear(); }, "curves: no curves"},
    {"empty id", [](CurveSet& s) { s.curves[1].id = ""; }, "curves[1].id: is empty"},
    {"duplicate id", [](CurveSet& s) { s.curves[1].id = "A"; },
     "curves[1].id: \"A\" is already the id of curves[0]"},
    {"start value", [](CurveSet& s) { s.curves[0].start.value = HUGE_VAL; },
     "curves[0].start.value: inf is not finite"},
    {"end frame", [](CurveSet& s) { s.curves[0].segments[1].end.frame = std::nan(""); },
     "curves[0].segments[1].end.frame: nan is not finite"},
    {"handle value", [](CurveSet& s) { s.curves[0].segments[1].handles[0].value = -HUGE_VAL; },
     "curves[0].segments[1].handles[0].value: -inf is not finite"},
    {"sample", [](CurveSet& s) { s.curves[1].samples[2] = std::nan(""); },
     "curves[1].samples[2]: nan is not finite"},
    {"first end at start", [](CurveSet& s) { s.curves[0].segments[0].end.frame = 0; },
     "curves[0].segments[0].end.frame: 0 must be greater than the previous point's frame 0"},
    {"ends decrease", [](CurveSet& s) { s.curves[0].segments[1].end.frame = 0.5; },
     "curves[0].segments[1].end.frame: 0.5 must be greater than the previous point's frame 1"},
    {"bad type", [](CurveSet& s) { s.curves[0].segments[0].type = static_cast<SegmentType>(7); },
     "curves[0].segments[0].type: 7 is not a segment type"},
    {"handle before span", [](CurveSet& s) { s.curves[0].segments[1].handles[0].frame = 0.5; },
     "curves[0].segments[1].handles[0].frame: 0.5 is outside the segment's time span [1, 3]"},
    {"handle after span", [](CurveSet& s) { s.curves[0].segments[1].handles[1].frame = 3.5; },
     "curves[0].segments[1].handles[1].frame: 3.5 is outside"},
    {"handles out of order", [](CurveSet& s) { s.curves[0].segments[1].handles[0].frame = 2.5; },
     "curves[0].segments[1].handles[1].frame: 2 is before handles[0].frame 2.5"},
    {"sample count", [](CurveSet& s) { s.curves[1].samples.pop_back(); },
     "curves[1].samples: expected 3 values (frame_count), got 2"},
};

TEST(ValidateCurveSetTest, RejectsEachBrokenRuleNamingPathAndValue) {
  for (const InvalidCase& c : kInvalidCases) {
    CurveSet set = ValidSet();
    c.mutate(set);
    EXPECT_THAT(ValidateCurveSet(set),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.name;
  }
}

TEST(ValidateCurveSetTest, HandleOrderMattersOnlyInRestrictedMode) {
  CurveSet set = ValidSet();
  set.curves[0].segments[1].handles[0].frame = 2.5;  // P1 after P2, both inside [1, 3]
  EXPECT_THAT(ValidateCurveSet(set),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("handles[1].frame")));
  set.beziers_restricted = false;
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
}

TEST(ValidateCurveSetTest, IgnoresTheUnusedFormOfADenseCurve) {
  CurveSet set = ValidSet();
  set.curves[1].start.value = std::nan("");  // unused: the curve is dense
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
}

}  // namespace
}  // namespace koma

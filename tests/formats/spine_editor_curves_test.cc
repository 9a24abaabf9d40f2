// Spine files as the editor writes them (issue 40): Beziers whose handles leave their
// segment's time span, read as the runtimes play them, and key times written to 4 decimals,
// taken as the frame they round to. The expectation of the runtimes' playback is computed
// here, literally from its description (docs/formats.md): sample the Bezier at u = k / 10 and,
// for a time t, interpolate towards the first sample at or after t from the one before it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"
#include "formats/spine.h"
#include "formats/spine_played_bezier.h"
#include "tests/formats/spine_test_util.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;
using Json = nlohmann::ordered_json;

// One Bezier segment of a timeline: keys (t0, v0) and (t1, v1), absolute handles (seconds).
struct Segment {
  double t0, v0, cx1, cy1, cx2, cy2, t1, v1;

  double Cubic(double p0, double p1, double p2, double p3, double u) const {
    const double w = 1 - u;
    return w * w * w * p0 + 3 * w * w * u * p1 + 3 * w * u * u * p2 + u * u * u * p3;
  }
  // The runtimes' value at t0 < t < t1.
  double Runtime(double t) const {
    double px = t0, py = v0;
    for (int k = 1; k <= 10; ++k) {
      const double u = k / 10.0;
      const double x = k == 10 ? t1 : Cubic(t0, cx1, cx2, t1, u);
      const double y = k == 10 ? v1 : Cubic(v0, cy1, cy2, v1, u);
      if (x >= t) return py + (t - px) * (y - py) / (x - px);
      px = x;
      py = y;
    }
    ADD_FAILURE() << "no sample at or after " << t;
    return 0;
  }
  // True when t is within `seconds` of a sample's time: where a jump of the runtime's value
  // may sit (koma draws a jump as a ramp 0.001 frame wide).
  bool NearASample(double t, double seconds) const {
    for (int k = 1; k <= 10; ++k) {
      const double x = k == 10 ? t1 : Cubic(t0, cx1, cx2, t1, k / 10.0);
      if (std::fabs(t - x) <= seconds) return true;
    }
    return false;
  }
};

// The curve at t seconds against `segment`'s runtime value, at 500 times across the segment
// (and the keys exactly). Returns how many times the runtime's value jumps (by more than
// `jump`) between neighbouring test times or onto the next key, so a test can require that
// its case has jumps.
int ExpectPlayedAsRuntime(const Curve& curve, const Segment& segment, double fps,
                          double jump = 1e300) {
  EXPECT_EQ(EvaluateCurve(curve, segment.t0 * fps, false), segment.v0);
  EXPECT_EQ(EvaluateCurve(curve, segment.t1 * fps, false), segment.v1);
  int jumps = 0;
  double previous = segment.v0;
  for (int j = 0; j < 500; ++j) {
    const double t = segment.t0 + (segment.t1 - segment.t0) * (j + 0.5) / 500;
    const double want = segment.Runtime(t);
    if (std::fabs(want - previous) > jump) ++jumps;
    previous = want;
    if (segment.NearASample(t, 2 * kSpineJumpFrames / fps)) continue;
    EXPECT_NEAR(EvaluateCurve(curve, t * fps, false), want, 1e-9 * (1 + std::fabs(want)))
        << curve.id << " at " << t << " s";
  }
  if (std::fabs(segment.v1 - previous) > jump) ++jumps;  // onto the next key at t1
  return jumps;
}

// The segment ends (key frames and the played points between them).
std::vector<double> EndFrames(const Curve& curve) {
  std::vector<double> frames{curve.start.frame};
  for (const CurveSegment& s : curve.segments) frames.push_back(s.end.frame);
  return frames;
}

SpineFile Parse(const std::string& text) {
  absl::StatusOr<SpineFile> file = ParseSpine(text);
  EXPECT_THAT(file.status(), IsOk());
  return file.ok() ? *std::move(file) : SpineFile{};
}

// A 4.1 skeleton as the editor writes it (times and handles to 4 decimals):
//  - rotate 0.2 s -> 0.6 s: the first handle at 0.05 s, before its key (an anticipation
//    dragged back in the graph view): the samples' time first runs back before 0.2 s;
//  - rotate 0.6 s -> 1 s: in span, kept as a Bezier;
//  - translate x 0 -> 1 s: the second handle at 1.3 s, past the next key (an overshoot), so the
//    samples pass 1 s before coming back; translate y of the same keys stays in span.
constexpr char kEditor41[] = R"({
  "skeleton": {"hash": "x", "spine": "4.1.24", "fps": 30},
  "bones": [{"name": "root"}, {"name": "tail", "parent": "root"}],
  "animations": {"jump": {"bones": {"tail": {
    "rotate": [
      {"time": 0.2, "curve": [0.05, -10, 0.5, 45]},
      {"time": 0.6, "value": 40, "curve": [0.7333, 40, 0.9, 5]},
      {"time": 1, "value": 0}],
    "translate": [
      {"x": 0, "y": 0, "curve": [0.3, 5, 1.3, 12, 0.25, 0, 0.75, 3]},
      {"time": 1, "x": 10, "y": 3}]
  }}}}})";

TEST(SpineEditorCurvesTest, Reads4xHandlesOutsideTheSpanAsTheRuntimesPlayThem) {
  const SpineFile file = Parse(kEditor41);
  const SpineAnimation& jump = file.animations[0];
  ASSERT_THAT(ValidateCurveSet(jump.curves), IsOk());

  const Curve& rotate = CurveNamed(jump, "tail/rotate");
  const Segment back{0.2, 0, 0.05, -10, 0.5, 45, 0.6, 40};
  EXPECT_GT(ExpectPlayedAsRuntime(rotate, back, 30, 1.0), 0) << "the case has no jump";
  // The keys stay where they were: 0 (the setup pose), 6, 18 and 30; straight pieces between
  // 6 and 18; the segment after 18, in span, is the Bezier as before.
  const std::vector<double> ends = EndFrames(rotate);
  EXPECT_EQ(ends[1], 6.0);
  EXPECT_THAT(ends, ::testing::Contains(18.0));
  EXPECT_EQ(ends.back(), 30.0);
  EXPECT_EQ(rotate.segments.back().type, SegmentType::kBezier);
  EXPECT_DOUBLE_EQ(rotate.segments.back().handles[0].frame, 0.7333 * 30);
  for (size_t s = 1; s + 1 < rotate.segments.size(); ++s) {
    EXPECT_EQ(rotate.segments[s].type, SegmentType::kLinear) << s;
  }
  EXPECT_EQ(EvaluateCurve(rotate, 3.0, false), 0.0);  // before its first key: the setup pose

  const Segment past{0, 0, 0.3, 5, 1.3, 12, 1, 10};
  EXPECT_GT(ExpectPlayedAsRuntime(CurveNamed(jump, "tail/translate.x"), past, 30, 0.1), 0);
  // Just before 1 s the runtime shows the line towards the sample past 1 s (9.88), then 10.
  EXPECT_NEAR(EvaluateCurve(CurveNamed(jump, "tail/translate.x"), 29.99, false),
              past.Runtime(29.99 / 30), 1e-9);
  EXPECT_LT(EvaluateCurve(CurveNamed(jump, "tail/translate.x"), 29.99, false), 9.9);
  const Curve& y = CurveNamed(jump, "tail/translate.y");
  ASSERT_EQ(y.segments.size(), 1u);  // in span: one exact Bezier, as before
  EXPECT_EQ(y.segments[0].type, SegmentType::kBezier);
}

// 3.7 and 3.8 with normalised handle times below 0 and above 1.
TEST(SpineEditorCurvesTest, Reads3xHandlesOutsideTheSpanAsTheRuntimesPlayThem) {
  constexpr char k37[] = R"({"skeleton": {"spine": "3.7.94"},
    "bones": [{"name": "root"}, {"name": "arm", "parent": "root"}],
    "animations": {"wave": {"bones": {"arm": {
      "rotate": [{"time": 0, "angle": 10, "curve": [-0.3, 0.2, 0.6, 1.1]},
                 {"time": 0.5, "angle": -20}],
      "translate": [{"time": 0, "x": 0, "y": 4, "curve": [0.25, 0, 1.4, 1]},
                    {"time": 1, "x": 8, "y": -4}]}}}}})";
  constexpr char k38[] = R"({"skeleton": {"spine": "3.8.99"},
    "bones": [{"name": "root"}, {"name": "arm", "parent": "root"}],
    "animations": {"wave": {"bones": {"arm": {
      "rotate": [{"time": 0, "angle": 10, "curve": -0.3, "c2": 0.2, "c3": 0.6, "c4": 1.1},
                 {"time": 0.5, "angle": -20}],
      "translate": [{"time": 0, "x": 0, "y": 4, "curve": 0.25, "c3": 1.4},
                    {"time": 1, "x": 8, "y": -4}]}}}}})";
  for (const char* text : {k37, k38}) {
    const SpineFile file = Parse(text);
    const SpineAnimation& wave = file.animations[0];
    ASSERT_THAT(ValidateCurveSet(wave.curves), IsOk());
    // Normalised: handle time t0 + cx (t1 - t0), value v0 + cy (v1 - v0).
    const Segment rotate{0, 10, -0.15, 10 + 0.2 * -30, 0.3, 10 + 1.1 * -30, 0.5, -20};
    EXPECT_GT(ExpectPlayedAsRuntime(CurveNamed(wave, "arm/rotate"), rotate, 30, 0.5), 0)
        << file.version;
    // One normalised curve for both values: x and y both converted.
    const Segment x{0, 0, 0.25, 0, 1.4, 8, 1, 8};
    const Segment y{0, 4, 0.25, 4, 1.4, -4, 1, -4};
    EXPECT_GT(ExpectPlayedAsRuntime(CurveNamed(wave, "arm/translate.x"), x, 30, 1.0), 0);
    EXPECT_GT(ExpectPlayedAsRuntime(CurveNamed(wave, "arm/translate.y"), y, 30, 1.0), 0);
  }
}

// A handle just past the span (cx2 = 1.01: the samples never pass the key) has no jump: the
// played curve is the straight pieces through the samples.
TEST(SpineEditorCurvesTest, AHandleJustOutsideIsTheSamplesJoined) {
  const SpineFile file = Parse(R"({"skeleton": {"spine": "3.8.99"},
    "bones": [{"name": "root"}],
    "animations": {"a": {"bones": {"root": {
      "rotate": [{"angle": 0, "curve": 0.3, "c2": 0.1, "c3": 1.01, "c4": 0.9},
                 {"time": 1, "angle": 90}]}}}}})");
  const Curve& rotate = file.animations[0].curves.curves[0];
  ASSERT_EQ(rotate.segments.size(), 10u);  // the 9 samples, then the key
  const Segment segment{0, 0, 0.3, 9, 1.01, 81, 1, 90};
  EXPECT_EQ(ExpectPlayedAsRuntime(rotate, segment, 30, 1.0), 0);
}

// SpinePlayedBezier on its own: increasing frames, the last the key; every jump a ramp.
TEST(SpineEditorCurvesTest, PlayedPointsIncreaseAndEndOnTheKey) {
  const CurvePoint controls[4] = {{6, 0}, {-30, 100}, {60, -100}, {18, 40}};  // far out
  const std::vector<CurvePoint> points = SpinePlayedBezier(controls);
  ASSERT_FALSE(points.empty());
  double previous = controls[0].frame;
  for (const CurvePoint& p : points) {
    EXPECT_GT(p.frame, previous);
    previous = p.frame;
  }
  EXPECT_EQ(points.back().frame, 18.0);
  EXPECT_EQ(points.back().value, 40.0);
  const CurvePoint too_far[4] = {{0, 0}, {HUGE_VAL, 1}, {2, 1}, {10, 1}};  // 1e308 s x 30 fps
  EXPECT_TRUE(SpinePlayedBezier(too_far).empty());
}

// Through core's RetimeCurves (on threes, the default) and back into the file: no error, and
// the converted timeline's JSON is written back untouched when it is not retimed.
TEST(SpineEditorCurvesTest, RetimesAndWritesBack) {
  const SpineFile file = Parse(kEditor41);
  const SpineAnimation& jump = file.animations[0];
  KomaUchiOptions options;
  ASSERT_THAT(ValidateKomaUchiOptions(options, jump.curves), IsOk());
  const KomaUchiResult result = RetimeCurves(jump.curves, options);
  ASSERT_EQ(result.curves.size(), jump.curves.curves.size());
  SpineRetimed retimed{0, {}};
  for (const RetimedCurve& curve : result.curves) {
    for (double value : curve.values) ASSERT_TRUE(std::isfinite(value));
    retimed.stepped.push_back(curve.steps);
  }
  absl::StatusOr<std::string> out = WriteSpine(file, {retimed});
  ASSERT_THAT(out.status(), IsOk());
  absl::StatusOr<SpineFile> again = ParseSpine(*out);
  ASSERT_THAT(again.status(), IsOk());
  // Every drawing shows the played curve at its time: the first drawing's value is the
  // rotate's setup pose, and the written keys are stepped.
  EXPECT_EQ(Json::parse(*out)["animations"]["jump"]["bones"]["tail"]["rotate"][0]["curve"],
            "stepped");

  // Only translate retimed: rotate (with its converted segment) keeps its JSON.
  SpineRetimed translate_only{0, std::vector<std::optional<std::vector<CurvePoint>>>(3)};
  translate_only.stepped[1] = result.curves[1].steps;
  translate_only.stepped[2] = result.curves[2].steps;
  absl::StatusOr<std::string> partial = WriteSpine(file, {translate_only});
  ASSERT_THAT(partial.status(), IsOk());
  const Json original = Json::parse(kEditor41);
  EXPECT_EQ(Json::parse(*partial)["animations"]["jump"]["bones"]["tail"]["rotate"],
            original["animations"]["jump"]["bones"]["tail"]["rotate"]);
  // Nothing retimed: the whole document as it came.
  absl::StatusOr<std::string> none = WriteSpine(file, {});
  ASSERT_THAT(none.status(), IsOk());
  EXPECT_EQ(Json::parse(*none), original);
}

// 1/6 s written as 0.1667 (frame 5.001 at 30 fps) is frame 5: a stepped key there switches on
// frame 5, and so does the retimed drawing; in 3.x and 4.x, and at 24 fps (1/24 s = 0.0417).
TEST(SpineEditorCurvesTest, FourDecimalKeyTimesAreTheirFrame) {
  constexpr char k42[] = R"({"skeleton": {"spine": "4.2.40"}, "bones": [{"name": "root"}],
    "animations": {"a": {"bones": {"root": {"rotate": [
      {"value": 0, "curve": "stepped"},
      {"time": 0.1667, "value": 10, "curve": [0.25, 10, 0.5, 30]},
      {"time": 0.6667, "value": 30}]}}}}})";
  constexpr char k38[] = R"({"skeleton": {"spine": "3.8.99"}, "bones": [{"name": "root"}],
    "animations": {"a": {"bones": {"root": {"rotate": [
      {"angle": 0, "curve": "stepped"},
      {"time": 0.1667, "angle": 10, "curve": 0.25, "c3": 0.75},
      {"time": 0.6667, "angle": 30}]}}}}})";
  for (const char* text : {k42, k38}) {
    const SpineFile file = Parse(text);
    const SpineAnimation& a = file.animations[0];
    const Curve& rotate = a.curves.curves[0];
    ASSERT_EQ(rotate.segments.size(), 2u);
    EXPECT_EQ(rotate.segments[0].end.frame, 5.0) << file.version;
    EXPECT_EQ(rotate.segments[1].end.frame, 20.0);
    EXPECT_EQ(EvaluateCurve(rotate, 4.999, false), 0.0);
    EXPECT_EQ(EvaluateCurve(rotate, 5.0, false), 10.0);
    EXPECT_EQ(EvaluateCurve(rotate, 20.0, false), 30.0);
    // Handles stay within the span between the keys' frames.
    EXPECT_GE(rotate.segments[1].handles[0].frame, 5.0);
    ASSERT_THAT(ValidateCurveSet(a.curves), IsOk());
    // Retimed on threes: key poses at 0, 5 and 20; the drawing from frame 5 shows the new pose.
    KomaUchiOptions options;
    const KomaUchiResult result = RetimeCurves(a.curves, options);
    EXPECT_EQ(result.key_frames, (std::vector<int>{0, 5, 20}));
    const std::vector<double>& values = result.curves[0].values;
    EXPECT_EQ(values[4], 0.0);
    EXPECT_EQ(values[5], 10.0) << "the stepped key's pose arrives on frame 5";
  }
  // At 24 fps, 1/24 s is written 0.0417 (frame 1.0008); 0.167 (3 decimals) is not a frame.
  const SpineFile fps24 = Parse(R"({"skeleton": {"spine": "4.1.24", "fps": 24},
    "bones": [{"name": "root"}], "animations": {"a": {"bones": {"root": {"rotate": [
      {"value": 0}, {"time": 0.0417, "value": 1}, {"time": 0.167, "value": 2}]}}}}})");
  const Curve& rotate = fps24.animations[0].curves.curves[0];
  EXPECT_EQ(rotate.segments[0].end.frame, 1.0);
  EXPECT_DOUBLE_EQ(rotate.segments[1].end.frame, 0.167 * 24);
}

// A handle of a 4.x segment ending at a key that moved to its frame is clamped to it.
TEST(SpineEditorCurvesTest, HandlesFollowAKeyMovedToItsFrame) {
  const SpineFile file = Parse(R"({"skeleton": {"spine": "4.0.64"}, "bones": [{"name": "root"}],
    "animations": {"a": {"bones": {"root": {"rotate": [
      {"value": 0, "curve": [0.0833, 0, 0.1667, 10]}, {"time": 0.1667, "value": 10}]}}}}})");
  const Curve& rotate = file.animations[0].curves.curves[0];
  ASSERT_EQ(rotate.segments.size(), 1u);
  EXPECT_EQ(rotate.segments[0].type, SegmentType::kBezier);
  EXPECT_EQ(rotate.segments[0].end.frame, 5.0);
  EXPECT_EQ(rotate.segments[0].handles[1].frame, 5.0);
  EXPECT_THAT(ValidateCurveSet(file.animations[0].curves), IsOk());
}

// Two keys that fall on one frame by the 4-decimal rule are refused, naming the key.
TEST(SpineEditorCurvesTest, TwoKeysOnOneFrameAreRefused) {
  const std::string text = R"({"skeleton": {"spine": "4.1.24"}, "bones": [{"name": "root"}],
    "animations": {"a": {"bones": {"root": {"rotate": [
      {"value": 0}, {"time": 0.16665, "value": 1}, {"time": 0.1667, "value": 2}]}}}}})";
  EXPECT_THAT(ParseSpine(text).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("animations.a.bones.root.rotate[2].time: 0.1667 s is frame 5, "
                                 "as the previous key's 0.16665 s")));
}

}  // namespace
}  // namespace koma::formats

// Spine files as the editor writes them (issue 40): key times written to 4 decimals, taken as
// the frame they round to.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"
#include "formats/spine.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

SpineFile Parse(const std::string& text) {
  absl::StatusOr<SpineFile> file = ParseSpine(text);
  EXPECT_THAT(file.status(), IsOk());
  return file.ok() ? *std::move(file) : SpineFile{};
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

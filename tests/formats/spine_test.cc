// ParseSpine / WriteSpine on the real 3.7 export (tests/testdata/spine/matt-3.7.json, from
// Rhubarb Lip Sync's Spine exporter tests, MIT) and the hand-written 3.8, 4.1 and 4.2 files
// (same skeleton; Beziers, shear, scale, setup-pose prefixes, both 4.x translate layouts).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "core/curves.h"
#include "formats/spine.h"
#include "tests/formats/test_files.h"
#include "tests/formats/spine_test_util.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using Json = nlohmann::ordered_json;

std::string SpineText(const std::string& name) {
  return ReadTestFile(KOMA_TESTDATA_DIR "/spine/" + name);
}

SpineFile Parse(const std::string& name) {
  absl::StatusOr<SpineFile> file = ParseSpine(SpineText(name));
  EXPECT_THAT(file.status(), IsOk()) << name;
  return file.ok() ? *std::move(file) : SpineFile{};
}

std::vector<std::string> Ids(const SpineAnimation& animation) {
  std::vector<std::string> ids;
  for (const Curve& curve : animation.curves.curves) ids.push_back(curve.id);
  return ids;
}

double At(const Curve& curve, double seconds, double fps = 30.0) {
  return EvaluateCurve(curve, seconds * fps, false);
}

TEST(SpineTest, ReadsTheRhubarb37Export) {
  const SpineFile file = Parse("matt-3.7.json");
  EXPECT_EQ(file.version, "3.7.94");
  EXPECT_EQ(file.major, 3);
  EXPECT_EQ(file.minor, 7);
  EXPECT_EQ(file.fps, 30.0);
  ASSERT_EQ(file.animations.size(), 2u);
  const SpineAnimation& shake = file.animations[0];
  EXPECT_EQ(shake.name, "shake_head");
  EXPECT_EQ(shake.duration, 1.5);
  EXPECT_EQ(shake.curves.frame_count, 46);
  ASSERT_EQ(Ids(shake), std::vector<std::string>{"head/rotate"});
  const Curve& rotate = shake.curves.curves[0];
  ASSERT_EQ(rotate.segments.size(), 4u);
  // Keys are exact, 0.1667 s (1/6 s to Spine's 4 decimals) on frame 5; a [0.25, 0, 0.75, 1]
  // ease is symmetric, so its middle is the mean.
  EXPECT_EQ(rotate.segments[0].end.frame, 5.0);
  EXPECT_DOUBLE_EQ(EvaluateCurve(rotate, 5.0, false), 10.02);
  EXPECT_DOUBLE_EQ(At(rotate, 0.5), -9.37);
  EXPECT_NEAR(EvaluateCurve(rotate, (5.0 + 15.0) / 2, false), (10.02 - 9.37) / 2, 1e-9);
  // Normalised handles: time t0 + cx (t1 - t0), value v0 + cy (v1 - v0), in frames, between
  // the keys' frames (0.1667 s is frame 5, 0.8333 s frame 25).
  EXPECT_EQ(rotate.segments[1].type, SegmentType::kBezier);
  EXPECT_DOUBLE_EQ(rotate.segments[1].handles[0].frame, 5 + 0.25 * (15 - 5));
  EXPECT_DOUBLE_EQ(rotate.segments[1].handles[0].value, 10.02);
  EXPECT_DOUBLE_EQ(rotate.segments[3].handles[0].frame, 25 + 0.574 * (45 - 25));
  EXPECT_DOUBLE_EQ(rotate.segments[3].handles[1].value, 0.0);
  const SpineAnimation& walk = file.animations[1];
  EXPECT_EQ(Ids(walk), (std::vector<std::string>{"torso/translate.x", "torso/translate.y"}));
  // [0, 0.5, 0.75, 1]: the first handle sits on the key in time, halfway up in value.
  EXPECT_DOUBLE_EQ(walk.curves.curves[1].segments[0].handles[0].value, 15.0);
  EXPECT_EQ(walk.curves.curves[1].segments[0].handles[0].frame, 0.0);
}

TEST(SpineTest, Reads38DefaultsAndSetupPosePrefixes) {
  const SpineFile file = Parse("hero-3.8.json");
  ASSERT_EQ(file.animations.size(), 3u);
  const SpineAnimation& walk = file.animations[0];
  EXPECT_EQ(Ids(walk), (std::vector<std::string>{"torso/rotate", "torso/translate.x",
                                                 "torso/translate.y", "head/shear.x",
                                                 "head/shear.y", "arm/scale.x", "arm/scale.y"}));
  EXPECT_EQ(walk.duration, 1.5);  // bones end at 1.5 s; events and draw order earlier
  // 3.8: curve 0.25 and c3 0.75 with c2 = 0 and c4 = 1 by default.
  const Curve& rotate = CurveNamed(walk, "torso/rotate");
  EXPECT_DOUBLE_EQ(rotate.segments[0].handles[0].frame, 0.125 * 30);
  EXPECT_DOUBLE_EQ(rotate.segments[0].handles[0].value, 0.0);
  EXPECT_DOUBLE_EQ(rotate.segments[0].handles[1].frame, 0.375 * 30);
  EXPECT_DOUBLE_EQ(rotate.segments[0].handles[1].value, 20.0);
  EXPECT_EQ(rotate.segments[1].type, SegmentType::kStepped);
  EXPECT_EQ(At(rotate, 0.99), 20.0);
  EXPECT_EQ(At(rotate, 1.0), -10.0);
  EXPECT_EQ(At(rotate, 1.5), 0.0);  // a missing angle is 0
  // Scale's missing values are 1, the neutral scale.
  EXPECT_EQ(CurveNamed(walk, "arm/scale.x").start.value, 1.0);
  EXPECT_DOUBLE_EQ(At(CurveNamed(walk, "arm/scale.y"), 1.2), 0.8);
  // The shear's first key is at 0.2 s: before it the setup pose (0), as the runtimes do.
  const Curve& shear_x = CurveNamed(walk, "head/shear.x");
  EXPECT_TRUE(walk.channels[3].from_setup);
  EXPECT_EQ(At(shear_x, 0.0), 0.0);
  EXPECT_EQ(At(shear_x, 0.19), 0.0);
  EXPECT_EQ(At(shear_x, 0.2), 5.0);
  EXPECT_EQ(At(shear_x, 1.0), -5.0);
  EXPECT_EQ(At(CurveNamed(walk, "head/shear.y"), 0.5) > 0.0, true);
  // An animation without bone timelines has nothing to retime, and is kept.
  EXPECT_EQ(file.animations[2].name, "blink");
  EXPECT_FALSE(file.animations[2].retimable());
}

TEST(SpineTest, The38And41FilesDescribeTheSameRotation) {
  const SpineFile v38 = Parse("hero-3.8.json");
  const SpineFile v41 = Parse("hero-4.1.json");
  EXPECT_EQ(v41.major, 4);
  EXPECT_EQ(v41.minor, 1);
  const Curve& a = CurveNamed(v38.animations[0], "torso/rotate");
  const Curve& b = CurveNamed(v41.animations[0], "torso/rotate");
  for (int f = 0; f <= 45; ++f) {
    EXPECT_NEAR(EvaluateCurve(a, f, false), EvaluateCurve(b, f, false), 1e-9) << "frame " << f;
  }
  // 4.x handles are absolute, one set per value: translate.y has its own.
  const Curve& y = CurveNamed(v41.animations[0], "torso/translate.y");
  EXPECT_DOUBLE_EQ(y.segments[1].handles[0].value, 14.0);
  EXPECT_DOUBLE_EQ(y.segments[1].handles[0].frame, 0.9 * 30);
}

TEST(SpineTest, Reads42SeparateTranslateLayout) {
  const SpineFile file = Parse("hero-4.2.json");
  ASSERT_EQ(file.animations.size(), 1u);
  const SpineAnimation& walk = file.animations[0];
  EXPECT_EQ(Ids(walk),
            (std::vector<std::string>{"torso/translate.x", "torso/translate.y", "torso/rotate",
                                      "head/shear.x", "head/shear.y", "arm/scale.y"}));
  EXPECT_EQ(walk.channels[0].timeline, "translatex");
  EXPECT_EQ(walk.channels[1].timeline, "translatey");
  const Curve& y = CurveNamed(walk, "torso/translate.y");
  EXPECT_EQ(At(y, 0.1), 0.0);  // setup pose before its first key at 0.1667 s (frame 5)
  EXPECT_EQ(EvaluateCurve(y, 4.999, false), 0.0);
  EXPECT_EQ(EvaluateCurve(y, 5.0, false), 2.0);
  EXPECT_EQ(EvaluateCurve(y, 20.0, false), 12.0);              // 0.6667 s: frame 20
  EXPECT_EQ(At(CurveNamed(walk, "head/shear.y"), 0.59), 0.0);  // stepped from 0
  EXPECT_EQ(At(CurveNamed(walk, "head/shear.y"), 0.6), 10.0);
}

// Nothing retimed: the same document, as parsed JSON.
TEST(SpineTest, WritesBackUnchangedWithoutReplacements) {
  for (const char* name : {"matt-3.7.json", "hero-3.8.json", "hero-4.1.json", "hero-4.2.json"}) {
    const SpineFile file = Parse(name);
    absl::StatusOr<std::string> text = WriteSpine(file, {});
    ASSERT_THAT(text.status(), IsOk());
    EXPECT_EQ(Json::parse(*text), Json::parse(SpineText(name))) << name;
    EXPECT_EQ(text->back(), '\n');
  }
}

// Replacements equal to the stepped keys already there keep the timeline as it was.
TEST(SpineTest, SteppedKeysThatDoNotChangeKeepTheirTimeline) {
  const std::string text = R"({"skeleton": {"spine": "4.0.64"}, "bones": [{"name": "b"}],
    "animations": {"a": {"bones": {"b": {"rotate": [
      {"value": 1, "curve": "stepped", "unknown": [1]}, {"time": 0.5, "value": 2}]}}}}})";
  absl::StatusOr<SpineFile> file = ParseSpine(text);
  ASSERT_THAT(file.status(), IsOk());
  SpineRetimed same{0, {std::vector<CurvePoint>{{0, 1}, {15, 2}}}};
  absl::StatusOr<std::string> out = WriteSpine(*file, {same});
  ASSERT_THAT(out.status(), IsOk());
  EXPECT_EQ(Json::parse(*out), Json::parse(text));
}

TEST(SpineTest, WritesSteppedKeysInTheFilesOwnLayout) {
  const SpineFile v38 = Parse("hero-3.8.json");
  const SpineAnimation& walk = v38.animations[0];
  SpineRetimed retimed{0, std::vector<std::optional<std::vector<CurvePoint>>>(7)};
  retimed.stepped[1] = std::vector<CurvePoint>{{0, 0}, {7.5, 10}, {45, 40}};  // translate.x
  retimed.stepped[2] = std::vector<CurvePoint>{{0, 0}, {3.75, 2}, {45, 12}};  // translate.y
  retimed.stepped[0] = std::vector<CurvePoint>{{0, 0}, {3.75, 5}, {45, -1}};  // rotate
  absl::StatusOr<std::string> out = WriteSpine(v38, {retimed});
  ASSERT_THAT(out.status(), IsOk());
  const Json written = Json::parse(*out);
  const Json& torso = written["animations"]["walk"]["bones"]["torso"];
  // One key per time of either value; x and y each held from their own points.
  EXPECT_EQ(torso["translate"], Json::parse(R"([
    {"time": 0, "x": 0, "y": 0, "curve": "stepped"},
    {"time": 0.125, "x": 0, "y": 2, "curve": "stepped"},
    {"time": 0.25, "x": 10, "y": 2, "curve": "stepped"},
    {"time": 1.5, "x": 40, "y": 12}])"));
  EXPECT_EQ(torso["rotate"][1], Json::parse(R"({"time": 0.125, "angle": 5, "curve": "stepped"})"));
  // Untouched: the other timelines, the slots, events, draw order and unknown fields.
  const Json original = Json::parse(SpineText("hero-3.8.json"));
  EXPECT_EQ(written["animations"]["walk"]["bones"]["head"],
            original["animations"]["walk"]["bones"]["head"]);
  EXPECT_EQ(written["animations"]["walk"]["slots"], original["animations"]["walk"]["slots"]);
  EXPECT_EQ(written["animations"]["walk"]["events"], original["animations"]["walk"]["events"]);
  EXPECT_EQ(written["koma_unknown_top"], original["koma_unknown_top"]);
  EXPECT_EQ(written["animations"]["idle"], original["animations"]["idle"]);
  // The written file reads back as the stepped curves.
  absl::StatusOr<SpineFile> again = ParseSpine(*out);
  ASSERT_THAT(again.status(), IsOk());
  const Curve& x = CurveNamed(again->animations[0], "torso/translate.x");
  EXPECT_EQ(EvaluateCurve(x, 7.4, false), 0.0);
  EXPECT_EQ(EvaluateCurve(x, 7.5, false), 10.0);
  EXPECT_EQ(EvaluateCurve(x, 44.9, false), 10.0);
  (void)walk;
}

TEST(SpineTest, Writes4xValueFields) {
  const SpineFile v42 = Parse("hero-4.2.json");
  SpineRetimed retimed{0, std::vector<std::optional<std::vector<CurvePoint>>>(6)};
  retimed.stepped[0] = std::vector<CurvePoint>{{0, 0}, {3.75, 7}, {45, 40}};
  retimed.stepped[2] = std::vector<CurvePoint>{{0, 0}, {45, 0}};
  absl::StatusOr<std::string> out = WriteSpine(v42, {retimed});
  ASSERT_THAT(out.status(), IsOk());
  const Json torso = Json::parse(*out)["animations"]["walk"]["bones"]["torso"];
  EXPECT_EQ(torso["translatex"][1], Json::parse(R"({"time": 0.125, "value": 7, "curve": "stepped"})"));
  EXPECT_EQ(torso["rotate"], Json::parse(R"([{"time": 0, "value": 0, "curve": "stepped"},
                                             {"time": 1.5, "value": 0}])"));
  EXPECT_EQ(Json::parse(*out)["skeleton"]["spine"], "4.2.40");  // written in its own version
}

TEST(SpineTest, FindsAnimationsByName) {
  const SpineFile file = Parse("hero-3.8.json");
  EXPECT_EQ(*FindSpineAnimation(file, "idle"), 1);
  EXPECT_THAT(FindSpineAnimation(file, "run").status(),
              ::koma::testing::StatusIs(absl::StatusCode::kNotFound,
                                        "no animation named \"run\" (the skeleton has \"walk\", "
                                        "\"idle\", \"blink\")"));
}

TEST(SpineTest, RefusesBadReplacements) {
  const SpineFile file = Parse("hero-4.2.json");
  SpineRetimed wrong_count{0, {std::vector<CurvePoint>{{0, 1}}}};
  EXPECT_THAT(WriteSpine(file, {wrong_count}).status(),
              ::koma::testing::StatusIs(absl::StatusCode::kInvalidArgument,
                                        ::testing::HasSubstr("expected one entry per curve")));
  SpineRetimed out_of_order{0, std::vector<std::optional<std::vector<CurvePoint>>>(6)};
  out_of_order.stepped[3] = std::vector<CurvePoint>{{5, 1}, {5, 2}};
  EXPECT_THAT(WriteSpine(file, {out_of_order}).status(),
              ::koma::testing::StatusIs(absl::StatusCode::kInvalidArgument,
                                        ::testing::HasSubstr("retimed[0].stepped[3][1].frame")));
  EXPECT_THAT(WriteSpine(file, {SpineRetimed{3, {}}}).status(),
              ::koma::testing::StatusIs(absl::StatusCode::kInvalidArgument,
                                        ::testing::HasSubstr("retimed[0].animation: 3")));
}

}  // namespace
}  // namespace koma::formats

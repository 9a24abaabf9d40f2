// ParseMotion3 / WriteMotion3 / CountMotion3 on samples/arm_head.motion3.json (made by
// samples/make_arm_head_motion3.py) and the hand-written tests/testdata/small.motion3.json.
#include "formats/motion3.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "core/curves.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::EndsWith;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using Json = nlohmann::ordered_json;
using Replacements = std::vector<std::optional<std::vector<CurvePoint>>>;

std::string SampleText() { return ReadTestFile(KOMA_SAMPLES_DIR "/arm_head.motion3.json"); }
std::string SmallText() { return ReadTestFile(KOMA_TESTDATA_DIR "/small.motion3.json"); }

Motion3Counts MetaCounts(const Json& document) {
  const Json& meta = document.at("Meta");
  return {meta.at("CurveCount").get<int>(), meta.at("TotalSegmentCount").get<int>(),
          meta.at("TotalPointCount").get<int>(), meta.at("UserDataCount").get<int>(),
          meta.at("TotalUserDataSize").get<int>()};
}

void ExpectPoint(const CurvePoint& point, double frame, double value) {
  EXPECT_EQ(point.frame, frame);
  EXPECT_EQ(point.value, value);
}

void ExpectSameCurves(const CurveSet& a, const CurveSet& b) {
  EXPECT_EQ(a.fps, b.fps);
  EXPECT_EQ(a.frame_count, b.frame_count);
  EXPECT_EQ(a.beziers_restricted, b.beziers_restricted);
  ASSERT_EQ(a.curves.size(), b.curves.size());
  for (size_t c = 0; c < a.curves.size(); ++c) {
    SCOPED_TRACE(a.curves[c].id);
    EXPECT_EQ(a.curves[c].id, b.curves[c].id);
    ExpectPoint(b.curves[c].start, a.curves[c].start.frame, a.curves[c].start.value);
    ASSERT_EQ(a.curves[c].segments.size(), b.curves[c].segments.size());
    for (size_t s = 0; s < a.curves[c].segments.size(); ++s) {
      const CurveSegment& x = a.curves[c].segments[s];
      const CurveSegment& y = b.curves[c].segments[s];
      EXPECT_EQ(x.type, y.type) << "segment " << s;
      for (int h = 0; h < 2; ++h) ExpectPoint(y.handles[h], x.handles[h].frame, x.handles[h].value);
      ExpectPoint(y.end, x.end.frame, x.end.value);
    }
  }
}

class ArmHeadSampleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    text_ = SampleText();
    absl::StatusOr<Motion3File> file = ParseMotion3(text_);
    ASSERT_THAT(file, IsOk());
    file_ = *std::move(file);
  }
  const Curve& CurveNamed(const std::string& id) const {
    for (const Curve& curve : file_.curves.curves) {
      if (curve.id == id) return curve;
    }
    ADD_FAILURE() << "no curve " << id;
    return file_.curves.curves.front();
  }
  std::string text_;
  Motion3File file_;
};

TEST_F(ArmHeadSampleTest, Is3SecondsAt30FpsWithRestrictedBeziers) {
  EXPECT_EQ(file_.curves.fps, 30.0);
  EXPECT_EQ(file_.curves.frame_count, 91);  // round(3 s x 30) + 1
  EXPECT_TRUE(file_.curves.beziers_restricted);
  std::vector<std::string> ids;
  for (const Curve& curve : file_.curves.curves) ids.push_back(curve.id);
  EXPECT_THAT(ids, ::testing::ElementsAre("ParamAngleX", "ParamAngleY", "ParamBodyAngleX",
                                          "ParamArmLA", "ParamArmRA"));
  EXPECT_THAT(file_.targets, ::testing::Each(std::string("Parameter")));
  EXPECT_EQ(file_.targets.size(), 5u);
  for (const Curve& curve : file_.curves.curves) EXPECT_FALSE(curve.dense());
}

TEST_F(ArmHeadSampleTest, PassesValidateCurveSet) {
  EXPECT_THAT(ValidateCurveSet(file_.curves), IsOk());
}

TEST_F(ArmHeadSampleTest, ConvertsSecondsToFramesIncludingBezierHandles) {
  const Curve& head = CurveNamed("ParamAngleX");
  ExpectPoint(head.start, 0, 0);
  ASSERT_EQ(head.segments.size(), 4u);
  EXPECT_EQ(head.segments[0].type, SegmentType::kBezier);
  ExpectPoint(head.segments[0].handles[0], 9, 0);    // 0.3 s: 1/3 of 0 .. 27
  ExpectPoint(head.segments[0].handles[1], 18, 25);  // 0.6 s: 2/3
  ExpectPoint(head.segments[0].end, 27, 25);         // 0.9 s
  EXPECT_EQ(head.segments[1].type, SegmentType::kLinear);
  ExpectPoint(head.segments[1].end, 45, 25);
  EXPECT_EQ(head.segments[3].type, SegmentType::kBezier);
  ExpectPoint(head.segments[3].handles[0], 78, -15);  // 2.6 s
  ExpectPoint(head.segments[3].end, 90, 0);
}

TEST_F(ArmHeadSampleTest, HasOneSteppedAndOneInverseSteppedHold) {
  const Curve& left = CurveNamed("ParamArmLA");
  EXPECT_EQ(left.segments.back().type, SegmentType::kStepped);
  ExpectPoint(left.segments.back().end, 90, 0);
  const Curve& right = CurveNamed("ParamArmRA");
  EXPECT_EQ(right.segments.front().type, SegmentType::kInverseStepped);
  ExpectPoint(right.segments.front().end, 9, 0);
}

TEST_F(ArmHeadSampleTest, MetaCountsEqualARecount) {
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(file_.document));
  EXPECT_EQ(counts, MetaCounts(file_.document));
  EXPECT_EQ(counts.curve_count, 5);
  EXPECT_EQ(counts.total_segment_count, 19);
  EXPECT_EQ(counts.total_point_count, 44);  // 5 first points + 11 Beziers x 3 + 6 others
  EXPECT_EQ(counts.user_data_count, 2);
  EXPECT_EQ(counts.total_user_data_size, 19);  // "look_right" + "look_left"
}

// nlohmann's tab layout is Python's json.dumps(indent="\t"), numbers included.
TEST_F(ArmHeadSampleTest, WritingWithoutReplacementsReproducesTheFile) {
  const Replacements none(file_.curves.curves.size());
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file_, none));
  EXPECT_EQ(written, text_);
}

TEST_F(ArmHeadSampleTest, SteppedTimesAreFramesOverFpsAndReadBackExactly) {
  Replacements stepped(file_.curves.curves.size());
  stepped[0] = std::vector<CurvePoint>{{0, 0}, {10, 12.5}, {30, 25}, {90, 0}};
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file_, stepped));
  ASSERT_OK_AND_ASSIGN(const Motion3File reread, ParseMotion3(written));
  // 10 / 30 in seconds with round-trip digits; 30 / 30 as an integer.
  EXPECT_EQ(reread.document["Curves"][0]["Segments"].dump(),
            "[0,0,2,0.3333333333333333,12.5,2,1,25,2,3,0]");
  const Curve& head = reread.curves.curves[0];
  ExpectPoint(head.start, 0, 0);
  ASSERT_EQ(head.segments.size(), 3u);
  const double frames[] = {10, 30, 90};
  for (int s = 0; s < 3; ++s) {
    EXPECT_EQ(head.segments[s].type, SegmentType::kStepped);
    EXPECT_EQ(head.segments[s].end.frame, frames[s]);
  }
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(reread.document));
  EXPECT_EQ(MetaCounts(reread.document), counts);
  EXPECT_EQ(counts.total_segment_count, 19 - 4 + 3);
  EXPECT_EQ(counts.total_point_count, 44 - 11 + 4);
}

TEST_F(ArmHeadSampleTest, OutputIsTabIndentedWithAFinalNewline) {
  Replacements stepped(file_.curves.curves.size());
  stepped[4] = std::vector<CurvePoint>{{0, 0}, {45, 8}};
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file_, stepped));
  EXPECT_THAT(written, StartsWith("{\n\t\"Version\": 3,\n\t\"Meta\": {\n\t\t\"Duration\": 3,\n"));
  EXPECT_THAT(written, EndsWith("\n}\n"));
  EXPECT_THAT(written, HasSubstr("\t\t\t\"Segments\": [\n\t\t\t\t0,\n\t\t\t\t0,\n\t\t\t\t2,\n"
                                 "\t\t\t\t1.5,\n\t\t\t\t8\n\t\t\t]"));
}

class SmallFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<Motion3File> file = ParseMotion3(SmallText());
    ASSERT_THAT(file, IsOk());
    file_ = *std::move(file);
  }
  Motion3File file_;
};

TEST_F(SmallFileTest, ReadsAllTargetsAndSegmentTypes) {
  EXPECT_EQ(file_.curves.fps, 24.0);
  EXPECT_EQ(file_.curves.frame_count, 25);
  EXPECT_FALSE(file_.curves.beziers_restricted);  // absent: the Cubism SDK's default
  EXPECT_THAT(file_.targets, ::testing::ElementsAre("Model", "Parameter", "PartOpacity"));
  ASSERT_EQ(file_.curves.curves.size(), 3u);
  const Curve& eye = file_.curves.curves[1];
  EXPECT_EQ(eye.id, "ParamEyeLOpen");
  ExpectPoint(eye.start, 0, 1);
  ASSERT_EQ(eye.segments.size(), 3u);
  EXPECT_EQ(eye.segments[0].type, SegmentType::kBezier);
  ExpectPoint(eye.segments[0].handles[0], 3, 1);  // 0.125 s x 24
  ExpectPoint(eye.segments[0].handles[1], 6, 0);
  ExpectPoint(eye.segments[0].end, 9, 0);
  EXPECT_EQ(eye.segments[1].type, SegmentType::kStepped);
  ExpectPoint(eye.segments[1].end, 12, 1);
  EXPECT_EQ(eye.segments[2].type, SegmentType::kInverseStepped);
  ExpectPoint(eye.segments[2].end, 24, 0.5);
  EXPECT_THAT(ValidateCurveSet(file_.curves), IsOk());
  const Curve& arm = file_.curves.curves[2];
  ASSERT_EQ(arm.segments.size(), 2u);
  ExpectPoint(arm.segments[0].end, 12, 1);
}

// TotalUserDataSize sums UTF-8 bytes: "blink" (5) + "é!" (3 bytes, 2 characters).
TEST_F(SmallFileTest, CountsUserDataValuesInBytes) {
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(file_.document));
  EXPECT_EQ(counts.total_user_data_size, 8);
  EXPECT_EQ(counts, MetaCounts(file_.document));
}

TEST_F(SmallFileTest, RoundTripKeepsCurvesAndTheDocument) {
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file_, Replacements(3)));
  ASSERT_OK_AND_ASSIGN(const Motion3File reread, ParseMotion3(written));
  ExpectSameCurves(file_.curves, reread.curves);
  EXPECT_EQ(reread.targets, file_.targets);
  EXPECT_EQ(reread.document, file_.document);  // the counts were right already
  ASSERT_OK_AND_ASSIGN(const std::string again, WriteMotion3(reread, Replacements(3)));
  EXPECT_EQ(again, written);
}

TEST_F(SmallFileTest, WrongCountsAreRecomputedAndNothingElseChanges) {
  Motion3File broken = file_;
  broken.document["Meta"]["TotalPointCount"] = 999;
  broken.document["Meta"]["CurveCount"] = 1;
  broken.document["Meta"]["TotalUserDataSize"] = 7;  // characters, not bytes
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(broken, Replacements(3)));
  ASSERT_OK_AND_ASSIGN(const Motion3File reread, ParseMotion3(written));
  EXPECT_EQ(reread.document, file_.document);
}

TEST_F(SmallFileTest, MissingCountsAreAppendedToMeta) {
  Motion3File file = file_;
  file.document["Meta"].erase("UserDataCount");
  file.document["Meta"].erase("TotalUserDataSize");
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file, Replacements(3)));
  ASSERT_OK_AND_ASSIGN(const Motion3File reread, ParseMotion3(written));
  std::vector<std::string> keys;
  for (const auto& item : reread.document["Meta"].items()) keys.push_back(item.key());
  EXPECT_THAT(keys, ::testing::ElementsAre("Duration", "Fps", "Loop", "FadeInTime", "FadeOutTime",
                                           "CurveCount", "TotalSegmentCount", "TotalPointCount",
                                           "Comment", "UserDataCount", "TotalUserDataSize"));
  EXPECT_EQ(MetaCounts(reread.document), MetaCounts(file_.document));
}

TEST_F(SmallFileTest, SteppedWriteKeepsEveryUntouchedField) {
  Replacements stepped(3);
  stepped[1] = std::vector<CurvePoint>{{0, 1}, {5, 0.5}, {10, 0}, {20, 1}};
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteMotion3(file_, stepped));
  ASSERT_OK_AND_ASSIGN(const Motion3File reread, ParseMotion3(written));
  const Json& before = file_.document;
  const Json& after = reread.document;
  for (const char* key : {"Version", "UserData", "Extra"})
    EXPECT_EQ(after[key], before[key]) << key;
  for (const char* key : {"Duration", "Fps", "Loop", "FadeInTime", "FadeOutTime", "Comment"}) {
    EXPECT_EQ(after["Meta"][key], before["Meta"][key]) << key;
  }
  EXPECT_EQ(after["Curves"][0], before["Curves"][0]);
  EXPECT_EQ(after["Curves"][2], before["Curves"][2]);
  Json eye = after["Curves"][1];
  EXPECT_EQ(eye.dump(), R"({"Target":"Parameter","Id":"ParamEyeLOpen","FadeInTime":0.1,)"
                        R"("Segments":[0,1,2,0.20833333333333334,0.5,2,0.4166666666666667,0,)"
                        R"(2,0.8333333333333334,1]})");
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(after));
  EXPECT_EQ(MetaCounts(after), counts);
  EXPECT_EQ(counts, (Motion3Counts{3, 1 + 3 + 2, 2 + 4 + 3, 2, 8}));
  ExpectPoint(reread.curves.curves[1].segments[0].end, 5, 0.5);
  ExpectPoint(reread.curves.curves[1].segments[2].end, 20, 1);
  EXPECT_THAT(ValidateCurveSet(reread.curves), IsOk());
}

// The spec's own example (Live2D/CubismSpecs FileFormats/motion3.json.md): 3 curves of one
// linear segment each, 6 points, UserData "hoge" and "fuga" with TotalUserDataSize 8.
TEST(CountMotion3Test, MatchesTheSpecExample) {
  const Json document = Json::parse(R"({
    "Version": 3,
    "Meta": {"Duration": 1, "Fps": 120, "CurveCount": 3, "TotalSegmentCount": 3,
             "TotalPointCount": 6, "UserDataCount": 2, "TotalUserDataSize": 8},
    "UserData": [{"Time": 1.234, "Value": "hoge"}, {"Time": 5.612, "Value": "fuga"}],
    "Curves": [
      {"Target": "Model", "Id": "Opacity", "Segments": [0, 0, 0, 1, 1]},
      {"Target": "Parameter", "Id": "EyeLOpen", "Segments": [0, 0, 0, 1, 1]},
      {"Target": "PartOpacity", "Id": "ArmL", "FadeInTime": 2, "FadeOutTime": 2,
       "Segments": [0, 0, 0, 1, 1]}]})");
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(document));
  EXPECT_EQ(counts, MetaCounts(document));
}

TEST(CountMotion3Test, WithoutUserDataCountsZero) {
  const Json document = Json::parse(
      R"({"Curves": [{"Target": "Model", "Id": "A", "Segments": [0, 0, 1, 0, 0, 0, 0, 1, 1]}]})");
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(document));
  EXPECT_EQ(counts, (Motion3Counts{1, 1, 4, 0, 0}));
}

TEST(WriteMotion3Test, RefusesBadReplacements) {
  ASSERT_OK_AND_ASSIGN(Motion3File file, ParseMotion3(SmallText()));
  const auto write = [&file](std::vector<CurvePoint> steps) {
    Replacements stepped(3);
    stepped[2] = std::move(steps);
    return WriteMotion3(file, stepped);
  };
  const absl::StatusCode kInvalid = absl::StatusCode::kInvalidArgument;
  EXPECT_THAT(write({{0, 1}}), StatusIs(kInvalid, HasSubstr("stepped[2]: expected at least 2")));
  EXPECT_THAT(write({{0, 1}, {4, 2}, {4, 3}}),
              StatusIs(kInvalid, HasSubstr("stepped[2][2].frame: 4 is not after the previous "
                                           "keyframe's frame 4")));
  EXPECT_THAT(write({{0, 1}, {4, std::nan("")}}),
              StatusIs(kInvalid, HasSubstr("stepped[2][1]: expected finite numbers")));
  EXPECT_THAT(WriteMotion3(file, Replacements(2)),
              StatusIs(kInvalid, HasSubstr("expected one entry per curve (3), got 2")));
  file.curves.fps = 0;
  EXPECT_THAT(WriteMotion3(file, Replacements(3)),
              StatusIs(kInvalid, HasSubstr("curves.fps: expected a number > 0, got 0")));
}

TEST(WriteMotion3Test, RefusesADocumentWithoutMeta) {
  ASSERT_OK_AND_ASSIGN(Motion3File file, ParseMotion3(SmallText()));
  file.document.erase("Meta");
  EXPECT_THAT(WriteMotion3(file, Replacements(3)),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("Meta: missing")));
}

}  // namespace
}  // namespace koma::formats

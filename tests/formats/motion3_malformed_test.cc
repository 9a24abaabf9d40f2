// Each malformed motion3.json is a small edit of kValid; every case names the error code and a
// message substring that starts with the JSON path.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "formats/motion3.h"
#include "tests/testing/replace_once.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// Curves[0] "A": a linear and a Bezier segment; Curves[1] "B": one stepped segment.
constexpr char kValid[] =
    R"({"Version":3,)"
    R"("Meta":{"Duration":1,"Fps":30,"AreBeziersRestricted":true,"CurveCount":2,)"
    R"("TotalSegmentCount":3,"TotalPointCount":7,"UserDataCount":1,"TotalUserDataSize":2},)"
    R"("Curves":[)"
    R"({"Target":"Parameter","Id":"A","FadeInTime":0.5,"Segments":[0,0,0,0.5,1,1,0.6,1,0.8,0,1,0]},)"
    R"({"Target":"Model","Id":"B","Segments":[0,1,2,1,0]}],)"
    R"("UserData":[{"Time":0.5,"Value":"hi"}]})";

// kValid with the only occurrence of `from` replaced by `to`.
std::string Edit(const std::string& from, const std::string& to) {
  return ::koma::testing::ReplaceOnce(kValid, from, to);
}

struct MalformedCase {
  std::string name;
  std::string text;
  absl::StatusCode code;
  std::string message;  // a substring of the error message
};

TEST(ParseMotion3MalformedTest, TheBaseIsValid) {
  ASSERT_OK_AND_ASSIGN(const Motion3File file, ParseMotion3(kValid));
  ASSERT_OK_AND_ASSIGN(const Motion3Counts counts, CountMotion3(file.document));
  EXPECT_EQ(counts, (Motion3Counts{2, 3, 7, 1, 2}));
}

TEST(ParseMotion3MalformedTest, ReportsPathAndValue) {
  const absl::StatusCode kInvalid = absl::StatusCode::kInvalidArgument;
  const std::string kSegmentsA = "[0,0,0,0.5,1,1,0.6,1,0.8,0,1,0]";
  const MalformedCase kCases[] = {
      {"empty", "", kInvalid, "invalid JSON at byte 1: parse error at line 1, column 1"},
      {"cut short", Edit(R"("hi"}]})", R"("hi"}])"), kInvalid, "invalid JSON at byte"},
      {"trailing comma", Edit("[0,1,2,1,0]", "[0,1,2,1,0,]"), kInvalid, "invalid JSON at byte"},
      {"top-level array", "[1]", kInvalid, "expected a JSON object at the top level, got an array"},
      {"too deep", std::string(40, '[') + std::string(40, ']'), kInvalid,
       "JSON nested deeper than 32 levels at byte 32"},
      {"no Meta", Edit(R"("Meta":)", R"("Mota":)"), kInvalid, "Meta: missing"},
      {"Meta not an object", Edit(R"("Meta":{)", R"("Meta":3,"M":{)"), kInvalid,
       "Meta: expected an object, got 3"},
      {"no Fps", Edit(R"("Fps":30,)", ""), kInvalid, "Meta.Fps: missing"},
      {"Fps zero", Edit(R"("Fps":30)", R"("Fps":0)"), kInvalid,
       "Meta.Fps: expected a number > 0, got 0"},
      {"Fps negative", Edit(R"("Fps":30)", R"("Fps":-30)"), kInvalid,
       "Meta.Fps: expected a number > 0, got -30"},
      {"Fps a string", Edit(R"("Fps":30)", R"("Fps":"30")"), kInvalid,
       "Meta.Fps: expected a number, got \"30\""},
      {"Fps overflows", Edit(R"("Fps":30)", R"("Fps":1e999)"), kInvalid,
       "invalid JSON: number overflow parsing '1e999'"},
      {"no Duration", Edit(R"("Duration":1,)", ""), kInvalid, "Meta.Duration: missing"},
      {"Duration negative", Edit(R"("Duration":1)", R"("Duration":-1)"), kInvalid,
       "Meta.Duration: expected a number >= 0 (seconds), got -1"},
      {"too many frames", Edit(R"("Duration":1)", R"("Duration":1e300)"),
       absl::StatusCode::kOutOfRange, "Meta.Duration x Meta.Fps: 1e+300 s x 30 fps"},
      {"restricted not a boolean",
       Edit(R"("AreBeziersRestricted":true)", R"("AreBeziersRestricted":1)"), kInvalid,
       "Meta.AreBeziersRestricted: expected true or false, got 1"},
      {"no Curves", Edit(R"("Curves":)", R"("Kurves":)"), kInvalid, "Curves: missing"},
      {"Curves a string", Edit(R"("Curves":[)", R"("Curves":"none","X":[)"), kInvalid,
       "Curves: expected an array, got \"none\""},
      {"Curves null", Edit(R"("Curves":[)", R"("Curves":null,"X":[)"), kInvalid,
       "Curves: expected an array, got null"},
      {"curve not an object", Edit(R"(,{"Target":"Model")", R"(,5,{"Target":"Model")"), kInvalid,
       "Curves[1]: expected an object, got 5"},
      {"unknown Target", Edit(R"("Target":"Model")", R"("Target":"Part")"), kInvalid,
       "Curves[1].Target: expected \"Model\", \"Parameter\" or \"PartOpacity\", got \"Part\""},
      {"no Target", Edit(R"("Target":"Model",)", ""), kInvalid, "Curves[1].Target: missing"},
      {"no Id", Edit(R"("Id":"B",)", ""), kInvalid, "Curves[1].Id: missing"},
      {"Id a number", Edit(R"("Id":"B")", R"("Id":7)"), kInvalid,
       "Curves[1].Id: expected a string, got 7"},
      {"FadeInTime a string", Edit(R"("FadeInTime":0.5)", R"("FadeInTime":"0.5")"), kInvalid,
       "Curves[0].FadeInTime: expected a number, got \"0.5\""},
      {"no Segments", Edit(R"(,"Segments":[0,1,2,1,0])", ""), kInvalid,
       "Curves[1].Segments: missing"},
      {"Segments an object", Edit("[0,1,2,1,0]", R"({"0":1})"), kInvalid,
       "Curves[1].Segments: expected an array, got an object"},
      {"empty Segments", Edit("[0,1,2,1,0]", "[]"), kInvalid,
       "Curves[1].Segments: expected the first point (2 numbers) and at least one segment, "
       "got 0 number(s)"},
      {"first point only", Edit("[0,1,2,1,0]", "[0,1]"), kInvalid,
       "Curves[1].Segments: expected the first point (2 numbers) and at least one segment, "
       "got 2 number(s)"},
      {"a string in Segments", Edit(kSegmentsA, "[0,0,0,\"x\",1,1,0.6,1,0.8,0,1,0]"), kInvalid,
       "Curves[0].Segments[3]: expected a number, got \"x\""},
      {"null in Segments", Edit(kSegmentsA, "[0,0,0,0.5,1,1,0.6,1,0.8,null,1,0]"), kInvalid,
       "Curves[0].Segments[9]: expected a number, got null"},
      {"unknown identifier", Edit(kSegmentsA, "[0,0,4,0.5,1,1,0.6,1,0.8,0,1,0]"), kInvalid,
       "Curves[0].Segments[2]: unknown segment identifier 4 (expected 0 linear, 1 bezier, 2 "
       "stepped or 3 inverse stepped)"},
      {"fractional identifier", Edit(kSegmentsA, "[0,0,0,0.5,1,1.5,0.6,1,0.8,0,1,0]"), kInvalid,
       "Curves[0].Segments[5]: unknown segment identifier 1.5"},
      {"negative identifier", Edit("[0,1,2,1,0]", "[0,1,-1,1,0]"), kInvalid,
       "Curves[1].Segments[2]: unknown segment identifier -1"},
      {"truncated stepped", Edit("[0,1,2,1,0]", "[0,1,2,1]"), kInvalid,
       "Curves[1].Segments[2]: a stepped segment needs 2 numbers after its identifier, the "
       "array has 1"},
      {"truncated bezier", Edit(kSegmentsA, "[0,0,0,0.5,1,1,0.6,1,0.8,0,1]"), kInvalid,
       "Curves[0].Segments[5]: a bezier segment needs 6 numbers after its identifier, the "
       "array has 5"},
      {"identifier without a point", Edit("[0,1,2,1,0]", "[0,1,2,1,0,3]"), kInvalid,
       "Curves[1].Segments[5]: an inverse stepped segment needs 2 numbers after its "
       "identifier, the array has 0"},
      {"UserData an object",
       Edit(R"("UserData":[{"Time":0.5,"Value":"hi"}])", R"("UserData":{"Time":0.5,"Value":"hi"})"),
       kInvalid, "UserData: expected an array, got an object"},
      {"UserData without Time", Edit(R"("Time":0.5,)", ""), kInvalid, "UserData[0].Time: missing"},
      {"UserData Value a number", Edit(R"("Value":"hi")", R"("Value":12)"), kInvalid,
       "UserData[0].Value: expected a string, got 12"},
  };
  for (const MalformedCase& test : kCases) {
    EXPECT_THAT(ParseMotion3(test.text), StatusIs(test.code, HasSubstr(test.message)))
        << test.name << ": " << test.text;
  }
}

// What the format can carry is accepted: ValidateCurveSet judges the curves later.
TEST(ParseMotion3MalformedTest, LeavesCurveSemanticsToValidateCurveSet) {
  const std::string kCases[] = {
      Edit("[0,1,2,1,0]", "[1,1,2,0,0]"),              // time runs backwards
      Edit(R"("Id":"B")", R"("Id":"A")"),              // duplicate id
      Edit(R"("Duration":1)", R"("Duration":0)"),      // a single frame
      Edit(R"("CurveCount":2)", R"("CurveCount":9)"),  // a wrong count
      Edit(R"("Version":3)", R"("Version":"three","Unknown":[1,{"x":null}])"),
  };
  for (const std::string& text : kCases) EXPECT_THAT(ParseMotion3(text), IsOk()) << text;
}

TEST(ParseMotion3MalformedTest, CountMotion3ChecksTheSameStructure) {
  const nlohmann::ordered_json document = nlohmann::ordered_json::parse(
      R"({"Curves":[{"Target":"Model","Id":"A","Segments":[0,0,9,1,1]}]})");
  EXPECT_THAT(CountMotion3(document),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("Curves[0].Segments[2]: unknown segment identifier 9")));
  nlohmann::ordered_json infinite = document;
  infinite["Curves"][0]["Segments"] = {0, 0, 0, std::numeric_limits<double>::infinity(), 1};
  EXPECT_THAT(CountMotion3(infinite),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("Curves[0].Segments[3]: expected a finite number, got inf")));
  EXPECT_THAT(CountMotion3(nlohmann::ordered_json::array()),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("top level")));
}

}  // namespace
}  // namespace koma::formats

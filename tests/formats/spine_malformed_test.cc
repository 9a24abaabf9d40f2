// Each malformed Spine skeleton is a small edit of a valid 3.8 or 4.1 one; every case names the
// error code and a message substring that starts with the JSON path.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "formats/spine.h"
#include "tests/testing/replace_once.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

constexpr char kValid38[] =
    R"({"skeleton":{"spine":"3.8.99"},"bones":[{"name":"root"},{"name":"arm","parent":"root"}],)"
    R"("animations":{"wave":{"bones":{"arm":{)"
    R"("rotate":[{"angle":1,"curve":0.25,"c3":0.75},{"time":0.5,"angle":9,"curve":"stepped"},{"time":1}],)"
    R"("translate":[{"x":1,"curve":[0.1,0.2,0.3,0.4]},{"time":1,"y":3}]}}}}})";

constexpr char kValid41[] =
    R"({"skeleton":{"spine":"4.1.24"},"bones":[{"name":"root"},{"name":"arm","parent":"root"}],)"
    R"("animations":{"wave":{"bones":{"arm":{)"
    R"("rotate":[{"value":1,"curve":[0.1,1,0.4,9]},{"time":0.5,"value":9,"curve":"stepped"},{"time":1}],)"
    R"("translate":[{"x":1,"curve":[0.1,1,0.9,2,0.1,0,0.9,3]},{"time":1,"x":2,"y":3}]}}}}})";

std::string Edit38(const std::string& from, const std::string& to) {
  return ::koma::testing::ReplaceOnce(kValid38, from, to);
}
std::string Edit41(const std::string& from, const std::string& to) {
  return ::koma::testing::ReplaceOnce(kValid41, from, to);
}

struct MalformedCase {
  std::string name;
  std::string text;
  absl::StatusCode code;
  std::string message;  // a substring of the error message
};

TEST(ParseSpineMalformedTest, TheBasesAreValid) {
  EXPECT_THAT(ParseSpine(kValid38).status(), IsOk());
  EXPECT_THAT(ParseSpine(kValid41).status(), IsOk());
}

TEST(ParseSpineMalformedTest, ReportsPathAndValue) {
  const absl::StatusCode kInvalid = absl::StatusCode::kInvalidArgument;
  const std::string kRotate = "animations.wave.bones.arm.rotate";
  const std::string kTranslate = "animations.wave.bones.arm.translate";
  const MalformedCase kCases[] = {
      {"empty", "", kInvalid, "invalid JSON at byte 1"},
      {"binary .skel", std::string("\x1b\x00kOmA\x05", 7) + "3.8.99", kInvalid,
       "binary Spine .skel files are not read"},
      {"UTF-16", std::string("\xFF\xFE{\0\"\0", 6), kInvalid,
       "the file is UTF-16 (little-endian, byte order mark FF FE), not UTF-8"},
      {"too deep", std::string(70, '[') + std::string(70, ']'), kInvalid,
       "JSON nested deeper than 64 levels"},
      {"top-level array", "[1]", kInvalid, "expected a JSON object at the top level"},
      {"no skeleton", Edit38(R"("skeleton")", R"("skeletn")"), kInvalid, "skeleton: missing"},
      {"version not a string", Edit38(R"("3.8.99")", "3.8"), kInvalid,
       "skeleton.spine: expected a string, got 3.8"},
      {"old version", Edit38("3.8.99", "3.6.53"), kInvalid,
       "skeleton.spine: \"3.6.53\" is not a Spine version koma reads (3.7, 3.8, 4.0, 4.1, 4.2)"},
      {"future version", Edit41("4.1.24", "4.3.01"), kInvalid, "\"4.3.01\" is not a Spine version"},
      {"bad fps", Edit38(R"("3.8.99")", R"("3.8.99","fps":0)"), kInvalid,
       "skeleton.fps: expected frames per second in (0, 1e6], got 0"},
      {"bones not an array",
       Edit38(R"("bones":[{"name":"root"},{"name":"arm","parent":"root"}])", R"("bones":{"arm":1})"),
       kInvalid, "bones: expected an array, got an object"},
      {"bone without a name", Edit38(R"({"name":"root"})", R"({"nome":"root"})"), kInvalid,
       "bones[0].name: missing"},
      // Bones as the Spine runtimes read them: unique names, a parent read before its child.
      {"duplicate bone name", Edit38(R"({"name":"arm","parent":"root"})", R"({"name":"root"})"),
       kInvalid, "bones[1].name: \"root\" is also the name of bones[0]"},
      {"parent missing", Edit38(R"("parent":"root")", R"("parent":"torso")"), kInvalid,
       "bones[1].parent: \"torso\" is no earlier bone: a parent comes before its children"},
      {"own parent", Edit38(R"("parent":"root")", R"("parent":"arm")"), kInvalid,
       "bones[1].parent: \"arm\" is the bone itself"},
      {"parent after its child (a cycle)",
       Edit38(R"([{"name":"root"},{"name":"arm","parent":"root"}])",
              R"([{"name":"root","parent":"arm"},{"name":"arm","parent":"root"}])"),
       kInvalid, "bones[0].parent: \"arm\" is no earlier bone"},
      {"parent not a string", Edit38(R"("parent":"root")", R"("parent":7)"), kInvalid,
       "bones[1].parent: expected a string"},
      {"animations not an object", Edit38(R"("animations":{"wave":)", R"("animations":[],"x":{"wave":)"),
       kInvalid, "animations: expected an object, got an array"},
      {"unknown bone", Edit38(R"("bones":{"arm")", R"("bones":{"leg")"), kInvalid,
       "animations.wave.bones.leg: no bone named \"leg\" in bones"},
      {"timelines not an array", Edit38(R"("translate":[{"x":1,"curve":[0.1,0.2,0.3,0.4]},{"time":1,"y":3}])", R"("translate":{"x":1})"),
       kInvalid, kTranslate + ": expected an array, got an object"},
      {"key not an object", Edit38(R"({"time":1}])", "7]"), kInvalid,
       kRotate + "[2]: expected an object, got 7"},
      {"time a string", Edit38(R"({"time":1}])", R"({"time":"1"}])"), kInvalid,
       kRotate + "[2].time: expected a number, got \"1\""},
      {"angle a string", Edit38(R"("angle":9)", R"("angle":"9")"), kInvalid,
       kRotate + "[1].angle: expected a number, got \"9\""},
      {"negative time", Edit38(R"({"angle":1,)", R"({"time":-1,"angle":1,)"), kInvalid,
       kRotate + "[0].time: expected seconds >= 0, got -1"},
      {"keys out of order", Edit38(R"({"time":1}])", R"({"time":0.25}])"), kInvalid,
       kRotate + "[2].time: 0.25 is not after the previous key's 0.5 (keys must be in time order)"},
      {"two keys at one time", Edit38(R"({"time":1}])", R"({"time":0.5}])"), kInvalid,
       kRotate + "[2].time: 0.5 is not after the previous key's 0.5"},
      {"unknown curve kind", Edit38(R"("curve":"stepped")", R"("curve":"smooth")"), kInvalid,
       kRotate + "[1].curve: unknown curve kind \"smooth\""},
      {"curve an object", Edit38(R"("curve":"stepped")", R"("curve":{})"), kInvalid,
       kRotate + "[1].curve: expected \"stepped\" or a Bezier's numbers, got an object"},
      {"3.x Bezier of 3", Edit38("[0.1,0.2,0.3,0.4]", "[0.1,0.2,0.3]"), kInvalid,
       kTranslate + "[0].curve: a Bezier needs 4 numbers (cx1, cy1, cx2, cy2), got 3"},
      {"3.x Bezier with a string", Edit38("[0.1,0.2,0.3,0.4]", R"([0.1,0.2,"x",0.4])"), kInvalid,
       kTranslate + "[0].curve[2]: expected a number, got \"x\""},
      {"3.x handle time too far out", Edit38("[0.1,0.2,0.3,0.4]", "[0.1,0.2,1e308,0.4]"), kInvalid,
       kTranslate + "[0].curve: the handles (cx1, cy1, cx2, cy2) 0.1, 0.2, 1e+308, 0.4 "
                    "are too far out to evaluate"},
      {"3.8 c2 a string", Edit38(R"("c3":0.75)", R"("c3":"a")"), kInvalid,
       kRotate + "[0].c3: expected a number, got \"a\""},
      {"c2 with an array", Edit38("[0.1,0.2,0.3,0.4]", R"([0.1,0.2,0.3,0.4],"c2":1)"), kInvalid,
       kTranslate + "[0].c2: only with a number \"curve\" (3.8)"},
      {"4.x timeline in 3.x", Edit38(R"("translate":)", R"("translatex":)"), kInvalid,
       "animations.wave.bones.arm.translatex: a Spine 4.x field in a Spine 3.8 file"},
      {"4.x value in 3.x", Edit38(R"("angle":9)", R"("value":9)"), kInvalid,
       kRotate + "[1].value: a Spine 4.x field in a Spine 3.8 file (3.8.99); this key's value is "
                 "\"angle\""},
      {"3.x angle in 4.x", Edit41(R"("value":9)", R"("angle":9)"), kInvalid,
       kRotate + "[1].angle: a Spine 3.x field in a Spine 4.1 file (4.1.24); this key's value is "
                 "\"value\""},
      {"3.x c2 in 4.x", Edit41(R"("curve":[0.1,1,0.4,9]})", R"("curve":[0.1,1,0.4,9],"c2":0})"),
       kInvalid, kRotate + "[0].c2: a Spine 3.x field in a Spine 4.1 file"},
      {"3.x curve number in 4.x", Edit41("[0.1,1,0.4,9]", "0.1"), kInvalid,
       kRotate + "[0].curve: a Spine 3.x field in a Spine 4.1 file (4.1.24); 4.x keys hold a "
                 "Bezier as an array of 4 numbers"},
      {"4.x rotate Bezier of 8", Edit41("[0.1,1,0.4,9]", "[0.1,1,0.4,9,0.1,1,0.4,9]"), kInvalid,
       kRotate + "[0].curve: a Bezier needs 4 numbers (cx1, cy1, cx2, cy2 per value), got 8"},
      {"4.x translate Bezier of 4", Edit41("[0.1,1,0.9,2,0.1,0,0.9,3]", "[0.1,1,0.9,2]"),
       kInvalid, kTranslate + "[0].curve: a Bezier needs 8 numbers"},
      {"4.x handle time too far out",
       Edit41("[0.1,1,0.9,2,0.1,0,0.9,3]", "[0.1,1,0.9,2,-1e307,0,0.9,3]"), kInvalid,
       kTranslate + "[0].curve: the handles (cx1, cy1, cx2, cy2) -1e+307, 0, 0.9, 3 are too"},
      {"two keys on one frame", Edit41(R"({"time":0.5,"value":9)", R"({"time":0.99995,"value":9)"),
       kInvalid, kRotate + "[2].time: 1 s is frame 30, as the previous key's 0.99995 s"},
      {"one curve keyed twice", Edit41(R"("translate":[)", R"("translatex":[{"value":1}],"translate":[)"),
       kInvalid, kTranslate + ": the curve \"arm/translate.x\" is keyed twice in this animation"},
      {"NaN-like number", Edit38(R"("angle":9)", R"("angle":1e999)"), kInvalid, "invalid JSON"},
  };
  for (const MalformedCase& c : kCases) {
    EXPECT_THAT(ParseSpine(c.text).status(), StatusIs(c.code, HasSubstr(c.message))) << c.name;
  }
}

// Handles outside their segment's time span are written by the Spine editor and played by the
// runtimes: read (as the runtimes play them, tests/formats/spine_editor_curves_test.cc).
TEST(ParseSpineMalformedTest, HandlesOutsideTheirSegmentAreRead) {
  EXPECT_THAT(ParseSpine(Edit38("[0.1,0.2,0.3,0.4]", "[0.1,0.2,1.3,0.4]")).status(), IsOk());
  EXPECT_THAT(ParseSpine(Edit38(R"("curve":0.25,"c3":0.75)", R"("curve":-0.5,"c3":0.75)")).status(),
              IsOk());
  EXPECT_THAT(
      ParseSpine(Edit41("[0.1,1,0.9,2,0.1,0,0.9,3]", "[0.1,1,0.9,2,-0.1,0,0.9,3]")).status(),
      IsOk());
  EXPECT_THAT(ParseSpine(Edit41("[0.1,1,0.4,9]", "[0.1,1,0.7,9]")).status(), IsOk());
}

// Timelines koma does not retime are kept without checks, as are unknown fields.
TEST(ParseSpineMalformedTest, OtherTimelinesAreNotChecked) {
  const std::string text = ::koma::testing::ReplaceOnce(
      kValid41, R"("rotate":[)", R"("inherit":[{"time":"x"}],"future":7,"rotate":[)");
  EXPECT_THAT(ParseSpine(text).status(), IsOk());
}

}  // namespace
}  // namespace koma::formats

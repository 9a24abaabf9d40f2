// Each malformed input is a small edit of kValid; every case names the error code and a message
// substring that starts with the line number.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "formats/bvh.h"
#include "tests/testing/replace_once.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// Line numbers are in the comments: the cases below refer to them.
constexpr char kValid[] =
    "HIERARCHY\n"                                   // 1
    "ROOT Hips\n"                                   // 2
    "{\n"                                           // 3
    "  OFFSET 0 0 0\n"                              // 4
    "  CHANNELS 3 Zrotation Xrotation Yrotation\n"  // 5
    "  JOINT Head\n"                                // 6
    "  {\n"                                         // 7
    "    OFFSET 0 1 0\n"                            // 8
    "    CHANNELS 1 Xrotation\n"                    // 9
    "    End Site\n"                                // 10
    "    {\n"                                       // 11
    "      OFFSET 0 1 0\n"                          // 12
    "    }\n"                                       // 13
    "  }\n"                                         // 14
    "}\n"                                           // 15
    "MOTION\n"                                      // 16
    "Frames: 2\n"                                   // 17
    "Frame Time: 0.04\n"                            // 18
    "1 2 3 4\n"                                     // 19
    "5 6 7 8\n";                                    // 20

// kValid with the only occurrence of `from` replaced by `to`.
std::string Edit(const std::string& from, const std::string& to) {
  return ::koma::testing::ReplaceOnce(kValid, from, to);
}

struct MalformedCase {
  std::string name;
  std::string text;
  std::string message;  // a substring of the error message
};

TEST(ParseBvhMalformedTest, TheBaseIsValid) { EXPECT_THAT(ParseBvh(kValid), IsOk()); }

TEST(ParseBvhMalformedTest, ReportsLineAndToken) {
  const MalformedCase kCases[] = {
      {"empty", "",
       "line 1: expected \"HIERARCHY\" at the start of the file, got end of "
       "file"},
      {"no HIERARCHY", Edit("HIERARCHY\n", "\n"), "line 2: expected \"HIERARCHY\""},
      {"no ROOT", "HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 1\n",
       "line 2: expected \"ROOT\", got \"MOTION\""},
      {"no joint name", Edit("ROOT Hips", "ROOT"),
       "line 3: expected a joint name after \"ROOT\", got \"{\""},
      {"no brace", Edit("ROOT Hips", "ROOT Hips Extra"),
       "line 2: expected \"{\" after ROOT \"Hips\", got \"Extra\""},
      {"unknown channel", Edit("Xrotation Yrotation", "Xrot Yrotation"),
       "line 5: unknown channel name \"Xrot\""},
      {"too many channels", Edit("CHANNELS 3 Z", "CHANNELS 7 Z"),
       "line 5: CHANNELS count 7 in joint \"Hips\" (line 2) is more than 6"},
      {"channel count not a number", Edit("CHANNELS 3 Z", "CHANNELS three Z"),
       "line 5: CHANNELS count: expected a non-negative integer, got "
       "\"three\""},
      {"repeated channel", Edit("Zrotation Xrotation Yrotation", "Zrotation Xrotation Zrotation"),
       "line 5: channel \"Zrotation\" listed twice in joint \"Hips\""},
      {"second CHANNELS", Edit("CHANNELS 1 Xrotation", "CHANNELS 1 Xrotation CHANNELS 0"),
       "line 9: second CHANNELS in joint \"Head\" (line 6)"},
      {"duplicate joint name", Edit("JOINT Head", "JOINT Hips"),
       "line 6: duplicate joint name \"Hips\" (first declared on line 2)"},
      {"second OFFSET", Edit("    OFFSET 0 1 0\n    CH", "    OFFSET 0 1 0 OFFSET 0 1 0\n    CH"),
       "line 8: second OFFSET in joint \"Head\""},
      {"missing OFFSET", Edit("    OFFSET 0 1 0\n    CH", "\n    CH"),
       "line 14: joint \"Head\" (line 6) has no OFFSET"},
      {"bad OFFSET number", Edit("    OFFSET 0 1 0\n    CH", "    OFFSET 0 1,5 0\n    CH"),
       "line 8: OFFSET y: invalid number \"1,5\""},
      {"short OFFSET", Edit("  OFFSET 0 0 0\n", "  OFFSET 0 0\n"),
       "line 5: OFFSET z: invalid number \"CHANNELS\""},
      {"End without Site", Edit("End Site", "End Sight"),
       "line 10: expected \"Site\" after \"End\", got \"Sight\""},
      {"End Site with channels", Edit("      OFFSET 0 1 0\n", "      OFFSET 0 1 0 CHANNELS 0\n"),
       "line 12: unexpected \"CHANNELS\" in End Site of joint \"Head\" (line "
       "10)"},
      {"End Site without OFFSET", Edit("      OFFSET 0 1 0\n", "\n"),
       "line 13: End Site of joint \"Head\" (line 10) has no OFFSET"},
      {"unknown keyword", Edit("  JOINT Head", "  ROTATION 5\n  JOINT Head"),
       "line 6: unexpected \"ROTATION\" in joint \"Hips\""},
      {"missing close brace", Edit("  }\n}\n", "}\n"),
       "line 15: \"MOTION\" inside joint \"Hips\" (line 2): missing \"}\""},
      {"extra close brace", Edit("}\nMOTION", "}\n}\nMOTION"),
       "line 16: expected \"ROOT\" or \"MOTION\", got \"}\""},
      {"truncated hierarchy", std::string(kValid).substr(0, std::string(kValid).find("    End")),
       "line 10: end of file inside joint \"Head\" (line 6): missing \"}\""},
      {"ROOT inside a joint", Edit("  JOINT Head", "  ROOT Head"),
       "line 6: \"ROOT\" inside joint \"Hips\" (line 2): missing \"}\""},
      {"no Frames", Edit("Frames: 2\n", "\n"),
       "line 18: expected \"Frames:\" after \"MOTION\", got \"Frame\""},
      {"negative Frames", Edit("Frames: 2", "Frames: -1"),
       "line 17: Frames: expected a non-negative integer, got \"-1\""},
      {"fractional Frames", Edit("Frames: 2", "Frames: 2.5"),
       "line 17: Frames: expected a non-negative integer, got \"2.5\""},
      {"Frames overflow", Edit("Frames: 2", "Frames: 99999999999"),
       "line 17: Frames: expected a non-negative integer, got \"99999999999\""},
      {"no Frame Time", Edit("Frame Time: 0.04\n", "\n"),
       "line 19: expected \"Frame\" after the frame count, got \"1\""},
      {"zero Frame Time", Edit("Time: 0.04", "Time: 0"),
       "line 18: Frame Time \"0\" must be > 0 seconds"},
      {"negative Frame Time", Edit("Time: 0.04", "Time: -0.04"),
       "line 18: Frame Time \"-0.04\" must be > 0 seconds"},
      {"infinite Frame Time", Edit("Time: 0.04", "Time: inf"),
       "line 18: Frame Time: invalid number \"inf\""},
      {"NaN Frame Time", Edit("Time: 0.04", "Time: nan"),
       "line 18: Frame Time: invalid number \"nan\""},
      {"bad value", Edit("5 6 7 8", "5 6 x 8"),
       "line 20: frame 1, channel 2 (\"Hips\" Yrotation): invalid number \"x\""},
      {"NaN value", Edit("1 2 3 4", "1 2 3 nan"),
       "line 19: frame 0, channel 3 (\"Head\" Xrotation): invalid number \"nan\""},
      {"value too large", Edit("1 2 3 4", "1e999 2 3 4"),
       "line 19: frame 0, channel 0 (\"Hips\" Zrotation): invalid number "
       "\"1e999\""},
      {"short frame", Edit("5 6 7 8", "5 6 7"),
       "line 20: expected 4 values per frame (frame 1 of 0..1), got 3 before "
       "the end of the file"},
      {"missing frame", Edit("5 6 7 8\n", ""),
       "line 19: expected 2 frames of 4 values, got 1 before the end of the "
       "file"},
      {"no values", std::string(kValid).substr(0, std::string(kValid).find("1 2 3 4")),
       "line 18: expected 2 frames of 4 values, got 0 before the end of the file"},
      {"extra value", Edit("5 6 7 8", "5 6 7 8 9"),
       "line 20: unexpected \"9\" after the last frame (expected 2 frames x 4 "
       "values = 8)"},
      {"extra partial frame", Edit("5 6 7 8\n", "5 6 7 8\n\n9 10 11\n"),
       "line 22: unexpected \"9\" after the last frame"},
      {"whole frame, then a partial one", Edit("5 6 7 8\n", "5 6 7 8\n9 10 11 12\n13\n"),
       "line 22: unexpected \"13\" after the last frame"},
      {"whole frame, then a word", Edit("5 6 7 8\n", "5 6 7 8\n9 10 11 12\nEND\n"),
       "line 22: unexpected \"END\" after the last frame"},
  };
  for (const MalformedCase& c : kCases) {
    EXPECT_THAT(ParseBvh(c.text),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.name;
  }
}

// More whole frames than "Frames:" says, as some exporters write them (assimp's Boxing_Toes:
// "Frames: 3069" and 3,070 rows): read them all, as Blender's importer does, with a warning
// naming both counts and the lines.
TEST(ParseBvhMalformedTest, ReadsWholeFramesAfterTheCountWithAWarning) {
  std::vector<std::string> warnings;
  const absl::StatusOr<SkeletalClip> one_more =
      ParseBvh(Edit("5 6 7 8\n", "5 6 7 8\n9 10 11 12\n"), &warnings);
  ASSERT_THAT(one_more.status(), IsOk());
  EXPECT_EQ(one_more->frame_count, 3);
  EXPECT_EQ(one_more->values,
            (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}));
  EXPECT_THAT(warnings, ::testing::ElementsAre(
                            "line 21: \"Frames: 2\" (line 17) but 3 frames follow; read all 3, "
                            "as Blender does"));

  warnings.clear();
  const absl::StatusOr<SkeletalClip> wrapped =
      ParseBvh(Edit("5 6 7 8\n", "5 6 7 8\n9 10\n11 12 13 14 15\n16\n"), &warnings);
  ASSERT_THAT(wrapped.status(), IsOk());
  EXPECT_EQ(wrapped->frame_count, 4);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("but 4 frames follow"));

  // A file that keeps the count warns of nothing; without a list the warning is dropped.
  warnings.clear();
  ASSERT_THAT(ParseBvh(kValid, &warnings).status(), IsOk());
  EXPECT_THAT(warnings, ::testing::IsEmpty());
  EXPECT_EQ(ParseBvh(Edit("5 6 7 8\n", "5 6 7 8\n9 10 11 12\n"))->frame_count, 3);
}

// A huge or binary token is quoted escaped and cut to 40 bytes.
TEST(ParseBvhMalformedTest, QuotesTokensShortAndEscaped) {
  const std::string long_name(50000, 'X');
  const absl::StatusOr<SkeletalClip> result = ParseBvh(Edit("Xrotation Y", long_name + " Y"));
  EXPECT_THAT(result, StatusIs(absl::StatusCode::kInvalidArgument,
                               HasSubstr("line 5: unknown channel name \"" + std::string(40, 'X') +
                                         "\"... (expected Xposition")));
  EXPECT_LT(result.status().message().size(), 300u);
  EXPECT_THAT(
      ParseBvh(Edit("JOINT Head", std::string("JOINT He\x01") + "ad OFFSET")),
      StatusIs(absl::StatusCode::kInvalidArgument,
               HasSubstr("line 6: expected \"{\" after JOINT \"He\\001ad\", got \"OFFSET\"")));
}

// A file cut off in the middle of a word (a partial copy or download) says so; the same bad
// word followed by anything, even just a line end, is an ordinary error.
TEST(ParseBvhMalformedTest, SaysWhenTheFileEndsInsideAWord) {
  const std::string valid(kValid);
  const std::string cut_in_channel = valid.substr(0, valid.find("Xrotation Y") + 4);  // "Xrot"
  EXPECT_THAT(ParseBvh(cut_in_channel),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("line 5: unknown channel name \"Xrot\" (expected Xposition, "
                                 "Yposition, Zposition, Xrotation, Yrotation or Zrotation) (the "
                                 "file ends in the middle of this word: is it cut short?)")));
  const std::string cut_in_keyword = valid.substr(0, valid.find("Time:") + 2);  // "Ti"
  EXPECT_THAT(ParseBvh(cut_in_keyword),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("got \"Ti\" (the file ends in the middle of this word")));
  for (const std::string& whole_word : {cut_in_channel + "\n", cut_in_channel + " ",
                                        Edit("Xrotation Yrotation", "Xrot Yrotation")}) {
    const absl::StatusOr<SkeletalClip> result = ParseBvh(whole_word);
    EXPECT_THAT(result, StatusIs(absl::StatusCode::kInvalidArgument,
                                 HasSubstr("unknown channel name \"Xrot\"")));
    EXPECT_THAT(result.status().message(), ::testing::Not(HasSubstr("cut short")));
  }
  // A cut right after a whole word (here the last "}", no line end) reports what is missing,
  // without the hint.
  const std::string cut_after_brace = valid.substr(0, valid.find("MOTION") - 1);
  EXPECT_THAT(ParseBvh(cut_after_brace),
              StatusIs(absl::StatusCode::kInvalidArgument, ::testing::Not(HasSubstr("cut short"))));
}

TEST(ParseBvhMalformedTest, ReportsLinesOfACrlfFile) {
  std::string text;
  for (const char* p = kValid; *p != '\0'; ++p)
    text += (*p == '\n') ? std::string("\r\n") : std::string(1, *p);
  const size_t at = text.find("6 7 8");
  text.replace(at, 5, "6 ?? 8");
  EXPECT_THAT(ParseBvh(text), StatusIs(absl::StatusCode::kInvalidArgument,
                                       HasSubstr("line 20: frame 1, channel 2")));
}

}  // namespace
}  // namespace koma::formats

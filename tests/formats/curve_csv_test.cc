#include "formats/curve_csv.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ParseCurveCsvTest, ReadsDenseCurvesInColumnOrder) {
  ASSERT_OK_AND_ASSIGN(
      const CurveSet set,
      ParseCurveCsv("frame,ParamAngleX,ParamAngleY\n0,1,2\n1,3,4.5\n2,-1,0\n", 24));
  EXPECT_EQ(set.fps, 24.0);
  EXPECT_EQ(set.frame_count, 3);
  ASSERT_EQ(set.curves.size(), 2u);
  EXPECT_EQ(set.curves[0].id, "ParamAngleX");
  EXPECT_EQ(set.curves[1].id, "ParamAngleY");
  EXPECT_TRUE(set.curves[0].dense());
  EXPECT_THAT(set.curves[0].samples, ElementsAre(1, 3, -1));
  EXPECT_THAT(set.curves[1].samples, ElementsAre(2, 4.5, 0));
  EXPECT_TRUE(set.curves[1].segments.empty());
}

TEST(ParseCurveCsvTest, ReadsTheCrlfFixture) {
  const std::string text = ReadTestFile(KOMA_TESTDATA_DIR "/curves_crlf.csv");
  ASSERT_NE(text.find("\r\n"), std::string::npos) << "the fixture lost its CRLF line endings";
  ASSERT_OK_AND_ASSIGN(const CurveSet set, ParseCurveCsv(text, 30));
  EXPECT_EQ(set.frame_count, 4);
  ASSERT_EQ(set.curves.size(), 2u);
  EXPECT_EQ(set.curves[1].id, "ParamEyeLOpen");  // no '\r' left on the last id
  EXPECT_THAT(set.curves[0].samples, ElementsAre(0, 2.5, 5, -1e-3));
  EXPECT_THAT(set.curves[1].samples, ElementsAre(1, 0.75, 0.5, 0));
}

TEST(ParseCurveCsvTest, TheLastLineBreakIsOptional) {
  ASSERT_OK_AND_ASSIGN(const CurveSet set, ParseCurveCsv("frame,A\n0,1\n1,2", 30));
  EXPECT_THAT(set.curves[0].samples, ElementsAre(1, 2));
}

TEST(WriteCurveCsvTest, WritesHeaderAndOneRowPerFrame) {
  EXPECT_EQ(WriteCurveCsv({"A", "B"}, {{0.5, 0.0083333, -0.0}, {-1, 90, 1e-7}}),
            "frame,A,B\n"
            "0,0.5,-1\n"
            "1,0.0083333,90\n"
            "2,0,1e-07\n");
}

TEST(WriteCurveCsvTest, NoCurvesIsJustTheFrameHeader) {
  EXPECT_EQ(WriteCurveCsv({}, {}), "frame\n");
}

TEST(CurveCsvRoundTripTest, ValuesComeBackBitForBit) {
  const std::vector<std::string> ids = {"ParamAngleX", "ParamArmLA"};
  const std::vector<std::vector<double>> values = {
      {0.1 + 0.2, 1.0 / 3.0, -12.5, std::numeric_limits<double>::denorm_min()},
      {1e300, -2.2250738585072014e-308, 123456789.125, 7}};
  ASSERT_OK_AND_ASSIGN(const CurveSet set, ParseCurveCsv(WriteCurveCsv(ids, values), 30));
  ASSERT_EQ(set.curves.size(), 2u);
  for (size_t c = 0; c < ids.size(); ++c) {
    EXPECT_EQ(set.curves[c].id, ids[c]);
    EXPECT_EQ(set.curves[c].samples, values[c]);
  }
}

struct MalformedCase {
  std::string text;
  std::string message;  // a substring of the error message
};

TEST(ParseCurveCsvTest, MalformedInputNamesLineAndColumn) {
  const MalformedCase kCases[] = {
      {"", "line 1: missing header"},
      {"\n0,1\n", "line 1: empty line (expected the header)"},
      {"time,A\n0,1\n", "line 1, column 1: expected \"frame\", got \"time\""},
      {"Frame,A\n0,1\n", "line 1, column 1: expected \"frame\", got \"Frame\""},
      {"frame\n0\n", "line 1: expected at least one curve id after \"frame\""},
      {"frame,A,,B\n0,1,2,3\n", "line 1, column 3: empty curve id"},
      {"frame,A,B,A\n0,1,2,3\n", "line 1, column 4: duplicate curve id \"A\" (also column 2)"},
      {"frame,A\"B\n0,1\n",
       "line 1, column 2: a quote inside an unquoted field (quote the whole "
       "field and double the quote: \"a\"\"b\")"},
      {"frame,\"A\"B\n0,1\n", "line 1, column 2: text after the closing quote of a quoted field"},
      {"frame,\"A\n0,1\n", "line 1, column 2: a quoted field is not closed (a \" is missing)"},
      {"frame,A\n0,\"1\n", "line 2, column 2: a quoted field is not closed"},
      {"frame,A,\"B\"\n0,1,2\n1,2,3,\"\n\"\n",
       "line 3: expected 3 fields (frame and 2 curves), got 4"},
      {"frame,\"A\nB\"\n0,x\n", "line 3, column 2 (\"A\\nB\"): invalid number \"x\""},
      {"frame;A\n0;1,5,0\n", "line 2, column 2 (\"A\"): invalid number \"1,5,0\""},
      {"frame;A\n0;1.000,5\n", "line 2, column 2 (\"A\"): invalid number \"1.000,5\""},
      {"\xEF\xBB\xBF\xEF\xBB\xBF"
       "frame,A\n0,1\n",
       "line 1, column 1: expected \"frame\""},
      {"frame,A\n", "line 2: expected a row for frame 0 after the header"},
      {"frame,A\n1,5\n", "line 2, column 1: expected frame 0, got \"1\""},
      {"frame,A\n0,1\n2,3\n", "line 3, column 1: expected frame 1, got \"2\""},
      {"frame,A\n0,1\n0,3\n", "line 3, column 1: expected frame 1, got \"0\""},
      {"frame,A\n0,1\n1.0,3\n", "line 3, column 1: expected frame 1, got \"1.0\""},
      {"frame,A\n-0,1\n", "line 2, column 1: expected frame 0, got \"-0\""},
      {"frame,A\n+0,1\n", "line 2, column 1: expected frame 0, got \"+0\""},
      {"frame,A\n,1\n", "line 2, column 1: expected frame 0, got \"\""},
      {"frame,A,B\n0,1,x\n", "line 2, column 3 (\"B\"): invalid number \"x\""},
      {"frame,A,B\n0,nan,1\n", "line 2, column 2 (\"A\"): invalid number \"nan\""},
      {"frame,A,B\n0,1,\n", "line 2, column 3 (\"B\"): invalid number \"\": empty"},
      {"frame,A\n0, 1\n", "line 2, column 2 (\"A\"): invalid number \" 1\""},
      {"frame,A\n0,1\r\r\n", "line 2, column 2 (\"A\"): invalid number \"1\\r\""},
      {"frame,A,B\n0,1\n", "line 2: expected 3 fields (frame and 2 curves), got 2"},
      {"frame,A\n0,1,2\n", "line 2: expected 2 fields (frame and 1 curve), got 3"},
      {"frame,A\n0,1\n\n1,2\n", "line 3: empty line"},
      {"frame,A\n0,1\n\n", "line 3: empty line"},
  };
  for (const MalformedCase& test : kCases) {
    EXPECT_THAT(ParseCurveCsv(test.text, 30),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(test.message)))
        << test.text;
  }
}

// RFC 4180: ids with separators, quotes, line breaks, spaces and non-ASCII text are quoted on
// write and come back unchanged.
TEST(CurveCsvRoundTripTest, AwkwardIdsComeBack) {
  const std::vector<std::string> ids = {
      "Param,X", "say \"hi\"", "two\nlines",  "crlf\r\nid",         "semi;colon", " padded ",
      "\"",      "\"\"",       "tab\tinside", "\xE5\x8F\xA3 mouth", "frame",      "plain"};
  std::vector<std::vector<double>> values;
  for (size_t c = 0; c < ids.size(); ++c) values.push_back({double(c), -0.5 * double(c)});
  const std::string text = WriteCurveCsv(ids, values);
  EXPECT_THAT(text, ::testing::StartsWith(
                        "frame,\"Param,X\",\"say \"\"hi\"\"\",\"two\nlines\",\"crlf\r\nid\","
                        "\"semi;colon\",\" padded \",\"\"\"\",\"\"\"\"\"\",tab\tinside,"));
  ASSERT_OK_AND_ASSIGN(const CurveSet set, ParseCurveCsv(text, 30));
  ASSERT_EQ(set.curves.size(), ids.size());
  for (size_t c = 0; c < ids.size(); ++c) {
    EXPECT_EQ(set.curves[c].id, ids[c]);
    EXPECT_EQ(set.curves[c].samples, values[c]);
  }
}

// Random ids over an alphabet of the characters that need care, 300 files: write, read back,
// same ids and values. The reference is the input itself.
TEST(CurveCsvRoundTripTest, RandomIdsComeBack) {
  const std::string alphabet = std::string("ab,;\"\r\n \t\\x") + "\xC3\xA9";
  uint64_t state = 0x6b6f6d61;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<size_t>(state >> 33);
  };
  for (int file = 0; file < 300; ++file) {
    std::vector<std::string> ids;
    const size_t count = 1 + next() % 5;
    while (ids.size() < count) {
      std::string id;
      const size_t length = 1 + next() % 8;
      for (size_t k = 0; k < length; ++k) id += alphabet[next() % alphabet.size()];
      if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
    }
    std::vector<std::vector<double>> values(ids.size(), {0.25, -1, 3e-9});
    SCOPED_TRACE(file);
    ASSERT_OK_AND_ASSIGN(const CurveSet set, ParseCurveCsv(WriteCurveCsv(ids, values), 30));
    ASSERT_EQ(set.curves.size(), ids.size());
    for (size_t c = 0; c < ids.size(); ++c) EXPECT_EQ(set.curves[c].id, ids[c]) << file;
  }
}

TEST(ParseCurveCsvTest, ReadsQuotedFieldsByteOrderMarkAndSemicolons) {
  // Excel's "CSV UTF-8": a byte order mark, CRLF, quoted header fields.
  ASSERT_OK_AND_ASSIGN(const CurveSet bom,
                       ParseCurveCsv("\xEF\xBB\xBF\"frame\",\"A\"\r\n0,1\r\n1,\"2.5\"\r\n", 30));
  EXPECT_EQ(bom.curves[0].id, "A");
  EXPECT_THAT(bom.curves[0].samples, ElementsAre(1, 2.5));
  // Excel in a comma-decimal locale: ';' separators and decimal commas.
  ASSERT_OK_AND_ASSIGN(const CurveSet semi,
                       ParseCurveCsv("\xEF\xBB\xBF"
                                     "frame;Param,X;B\r\n0;0,5;-1\r\n1;2;1e-3\r\n",
                                     30));
  ASSERT_EQ(semi.curves.size(), 2u);
  EXPECT_EQ(semi.curves[0].id, "Param,X");
  EXPECT_THAT(semi.curves[0].samples, ElementsAre(0.5, 2));
  EXPECT_THAT(semi.curves[1].samples, ElementsAre(-1, 1e-3));
  // The same numbers with '.' in a ';' file.
  ASSERT_OK_AND_ASSIGN(const CurveSet dots, ParseCurveCsv("frame;A\n0;0.5\n", 30));
  EXPECT_THAT(dots.curves[0].samples, ElementsAre(0.5));
  // A ',' file's values never take a decimal comma: "0,5" is two fields.
  EXPECT_THAT(ParseCurveCsv("frame,A\n0,0,5\n", 30),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("line 2: expected 2 fields (frame and 1 curve), got 3")));
}

TEST(ParseCurveCsvTest, RefusesABadFrameRate) {
  for (const double fps : {0.0, -24.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_THAT(
        ParseCurveCsv("frame,A\n0,1\n", fps),
        StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("fps: expected a number > 0")))
        << fps;
  }
}

}  // namespace
}  // namespace koma::formats

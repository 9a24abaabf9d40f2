// Text encodings at the start of a file (formats/text_encoding.h), and every text reader with
// them: a UTF-8 byte order mark is skipped by the BVH, motion3.json and curve CSV readers (the
// same result as without it), UTF-16 and UTF-32 are refused naming the encoding.
#include "formats/text_encoding.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "formats/bvh.h"
#include "formats/curve_csv.h"
#include "formats/motion3.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;
using namespace std::string_literals;

constexpr const char* kUtf8BomBytes = "\xEF\xBB\xBF";

// `ascii` as UTF-16 (each byte then a NUL, or a NUL then each byte), with `bom` in front.
std::string Utf16(const std::string& ascii, bool little_endian, const std::string& bom) {
  std::string out = bom;
  for (char c : ascii) {
    out += little_endian ? std::string{c, '\0'} : std::string{'\0', c};
  }
  return out;
}

TEST(SkipUtf8BomTest, SkipsOneUtf8ByteOrderMark) {
  EXPECT_EQ(SkipUtf8Bom("\xEF\xBB\xBFHIERARCHY").value(), "HIERARCHY");
  EXPECT_EQ(SkipUtf8Bom("HIERARCHY").value(), "HIERARCHY");
  EXPECT_EQ(SkipUtf8Bom("").value(), "");
  EXPECT_EQ(SkipUtf8Bom("\xEF\xBB\xBF").value(), "");
  // Only one: a second mark is the file's content (and its reader's error).
  EXPECT_EQ(SkipUtf8Bom("\xEF\xBB\xBF\xEF\xBB\xBFx").value(), "\xEF\xBB\xBFx");
  EXPECT_EQ(SkipUtf8Bom("\xEF\xBB").value(), "\xEF\xBB");  // cut short: not a mark
  EXPECT_EQ(SkipUtf8Bom("x").value(), "x");
}

TEST(SkipUtf8BomTest, NamesUtf16AndUtf32) {
  const struct {
    std::string text;
    const char* encoding;
  } cases[] = {
      {Utf16("HIERARCHY", true, "\xFF\xFE"), "UTF-16 (little-endian, byte order mark FF FE)"},
      {Utf16("HIERARCHY", false, "\xFE\xFF"), "UTF-16 (big-endian, byte order mark FE FF)"},
      {Utf16("HIERARCHY", true, ""), "UTF-16 (little-endian, no byte order mark)"},
      {Utf16("{", false, ""), "UTF-16 (big-endian, no byte order mark)"},
      {Utf16("\r\n", true, ""), "UTF-16 (little-endian, no byte order mark)"},
      {"\xFF\xFE\0\0H\0\0\0"s, "UTF-32 (little-endian, byte order mark FF FE 00 00)"},
      {"\0\0\xFE\xFF\0\0\0H"s, "UTF-32 (big-endian, byte order mark 00 00 FE FF)"},
  };
  for (const auto& c : cases) {
    EXPECT_THAT(SkipUtf8Bom(c.text).status(),
                StatusIs(absl::StatusCode::kInvalidArgument,
                         "the file is "s + c.encoding + ", not UTF-8: save it as UTF-8"))
        << c.encoding;
  }
}

TEST(TextReadersTest, BvhWithAByteOrderMarkReadsAsWithout) {
  const std::string text = ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh");
  const absl::StatusOr<SkeletalClip> plain = ParseBvh(text);
  const absl::StatusOr<SkeletalClip> marked = ParseBvh(kUtf8BomBytes + text);
  ASSERT_TRUE(plain.ok()) << plain.status();
  ASSERT_TRUE(marked.ok()) << marked.status();
  EXPECT_EQ(WriteBvh(*marked), WriteBvh(*plain));
  // Line numbers in errors still count from the file's first line.
  EXPECT_THAT(
      ParseBvh(std::string(kUtf8BomBytes) + "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n").status(),
      StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 4: ")));
  EXPECT_THAT(ParseBvh(Utf16(text.substr(0, 200), true, "\xFF\xFE")).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("the file is UTF-16 (little-endian, byte order mark FF FE)")));
}

TEST(TextReadersTest, Motion3WithAByteOrderMarkReadsAsWithout) {
  const std::string text = ReadTestFile(KOMA_TESTDATA_DIR "/small.motion3.json");
  const absl::StatusOr<Motion3File> plain = ParseMotion3(text);
  const absl::StatusOr<Motion3File> marked = ParseMotion3(kUtf8BomBytes + text);
  ASSERT_TRUE(plain.ok()) << plain.status();
  ASSERT_TRUE(marked.ok()) << marked.status();
  EXPECT_EQ(marked->document, plain->document);
  EXPECT_EQ(marked->curves.curves.size(), plain->curves.curves.size());
  EXPECT_THAT(ParseMotion3(Utf16(text.substr(0, 100), false, "\xFE\xFF")).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("the file is UTF-16 (big-endian, byte order mark FE FF)")));
  EXPECT_THAT(ParseMotion3(Utf16(text.substr(0, 100), true, "")).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("UTF-16 (little-endian, no byte order mark)")));
}

TEST(TextReadersTest, CurveCsvWithAByteOrderMarkReadsAsWithout) {
  const std::string text = "frame,A,B\n0,1,2\n1,3,4.5\n";
  const absl::StatusOr<CurveSet> plain = ParseCurveCsv(text, 30);
  const absl::StatusOr<CurveSet> marked = ParseCurveCsv(kUtf8BomBytes + text, 30);
  ASSERT_TRUE(plain.ok()) << plain.status();
  ASSERT_TRUE(marked.ok()) << marked.status();
  ASSERT_EQ(marked->curves.size(), 2u);
  EXPECT_EQ(marked->curves[0].id, "A");
  EXPECT_EQ(marked->curves[1].samples, plain->curves[1].samples);
  EXPECT_THAT(ParseCurveCsv(Utf16(text, true, "\xFF\xFE"), 30).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("the file is UTF-16 (little-endian, byte order mark FF FE)")));
}

}  // namespace
}  // namespace koma::formats

#include "formats/number_format.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

uint64_t Bits(double value) {
  uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

TEST(FormatDoubleTest, WritesShortestFixedTextForOrdinaryMagnitudes) {
  EXPECT_EQ(FormatDouble(0.0), "0");
  EXPECT_EQ(FormatDouble(1.0), "1");
  EXPECT_EQ(FormatDouble(90.0), "90");
  EXPECT_EQ(FormatDouble(-12.5), "-12.5");
  EXPECT_EQ(FormatDouble(0.0083333), "0.0083333");
  EXPECT_EQ(FormatDouble(0.0416667), "0.0416667");
  EXPECT_EQ(FormatDouble(123456.789), "123456.789");
  EXPECT_EQ(FormatDouble(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(FormatDouble(1.0 / 120.0), "0.008333333333333333");
  EXPECT_EQ(FormatDouble(1e-6), "0.000001");
  EXPECT_EQ(FormatDouble(9007199254740992.0), "9007199254740992");  // 2^53
}

TEST(FormatDoubleTest, UsesExponentOutsideTheFixedRange) {
  EXPECT_EQ(FormatDouble(1e-7), "1e-07");
  EXPECT_EQ(FormatDouble(-2.5e-9), "-2.5e-09");
  EXPECT_EQ(FormatDouble(1e16), "1e+16");
  EXPECT_EQ(FormatDouble(1.5e20), "1.5e+20");
  EXPECT_EQ(FormatDouble(5e-324), "5e-324");
  EXPECT_EQ(FormatDouble(std::numeric_limits<double>::max()), "1.7976931348623157e+308");
}

TEST(FormatDoubleTest, NegativeZeroIsWrittenAsZero) { EXPECT_EQ(FormatDouble(-0.0), "0"); }

TEST(FormatDoubleTest, NonFiniteValuesHaveNamesThatParseDoubleRejects) {
  EXPECT_EQ(FormatDouble(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatDouble(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatDouble(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_FALSE(ParseDouble("nan").ok());
  EXPECT_FALSE(ParseDouble("-inf").ok());
}

// Random bit patterns cover every exponent; each finite one must read back bit for bit.
TEST(FormatDoubleTest, RoundTripsRandomBitPatternsExactly) {
  std::mt19937_64 rng(20240607);
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    const uint64_t bits = rng();
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof value);
    if (!std::isfinite(value) || value == 0.0) continue;
    const std::string text = FormatDouble(value);
    const absl::StatusOr<double> back = ParseDouble(text);
    ASSERT_THAT(back, IsOk()) << text;
    ASSERT_EQ(Bits(*back), bits) << text;
    ++checked;
  }
  EXPECT_GT(checked, 190000);
}

// Shortest: a decimal with few digits comes back as the same text, not 17 digits.
TEST(FormatDoubleTest, ShortDecimalsKeepTheirText) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const int64_t mantissa = static_cast<int64_t>(rng() % 2000000) - 1000000;  // 7 digits
    if (mantissa == 0 || mantissa % 10 == 0) continue;  // a trailing zero would be dropped
    const int decimals = static_cast<int>(rng() % 6);
    std::string text = std::to_string(std::llabs(mantissa));
    if (decimals > 0) {
      while (static_cast<int>(text.size()) <= decimals) text.insert(0, "0");
      text.insert(text.size() - decimals, ".");
    }
    if (mantissa < 0) text.insert(0, "-");
    ASSERT_OK_AND_ASSIGN(const double value, ParseDouble(text));
    ASSERT_EQ(FormatDouble(value), text);
  }
}

TEST(ParseDoubleTest, AcceptsTheNumberFormsFoundInBvhFiles) {
  const struct {
    const char* text;
    double expected;
  } kCases[] = {
      {"0", 0.0},        {"42", 42.0},   {"-7.25", -7.25}, {".0083333", 0.0083333}, {"-.5", -0.5},
      {"+2", 2.0},       {"+.5", 0.5},   {"5.", 5.0},      {"1e-3", 0.001},         {"1E3", 1000.0},
      {"-2.5e+2", -250}, {"0.000", 0.0}, {"007", 7.0},     {"4.9e-324", 4.9e-324},
  };
  for (const auto& c : kCases) {
    const absl::StatusOr<double> value = ParseDouble(c.text);
    ASSERT_THAT(value, IsOk()) << c.text;
    EXPECT_EQ(*value, c.expected) << c.text;
  }
}

TEST(ParseDoubleTest, KeepsTheSignOfNegativeZero) {
  ASSERT_OK_AND_ASSIGN(const double value, ParseDouble("-0"));
  EXPECT_TRUE(std::signbit(value));
}

TEST(ParseDoubleTest, RejectsEverythingElseQuotingTheText) {
  const char* const kCases[] = {
      "",    " 1",  "1 ",   "1x",   "+",        "-",     "+-1",    "--1",    "++1",   "-+1",
      ".",   "e5",  "1e",   "1e+",  "1.2.3",    "1,5",   "0x10",   "1f",     "12abc", "nan",
      "NaN", "inf", "-inf", "+inf", "infinity", "1e400", "-1e400", "1e-400",
  };
  for (const char* text : kCases) {
    EXPECT_THAT(ParseDouble(text),
                StatusIs(absl::StatusCode::kInvalidArgument,
                         HasSubstr(std::string("invalid number \"") + text + "\"")))
        << "text: [" << text << "]";
  }
}

// Messages stay short and printable whatever the input.
TEST(ParseDoubleTest, QuotesEscapedAndShortened) {
  EXPECT_THAT(ParseDouble("\t1"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("invalid number \"\\t1\"")));
  const std::string long_text(100000, '7');
  const absl::StatusOr<double> result = ParseDouble(long_text + "x");
  EXPECT_THAT(result, StatusIs(absl::StatusCode::kInvalidArgument,
                               HasSubstr("invalid number \"" + std::string(40, '7') + "\"...")));
  EXPECT_LT(result.status().message().size(), 200u);
}

TEST(ParseDoubleTest, ExplainsWhy) {
  EXPECT_THAT(ParseDouble("12abc"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("unexpected \"abc\"")));
  EXPECT_THAT(ParseDouble("1e400"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("range of a double")));
  EXPECT_THAT(ParseDouble(""), StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("empty")));
}

// The string_view need not be NUL-terminated: only its own characters are read.
TEST(ParseDoubleTest, ReadsOnlyTheGivenCharacters) {
  const std::string_view text("1.25xyz", 3);  // "1.2"
  ASSERT_OK_AND_ASSIGN(const double value, ParseDouble(text));
  EXPECT_EQ(value, 1.2);
}

}  // namespace
}  // namespace koma::formats

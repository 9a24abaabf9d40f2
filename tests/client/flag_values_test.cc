// Flag values: each bad value gets one exact, readable message (the first line a user sees).
#include "client/flag_values.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::Eq;

constexpr auto kInvalid = absl::StatusCode::kInvalidArgument;

TEST(FlagValuesTest, WholeNumbers) {
  EXPECT_EQ(*ParseWholeNumber("--omit", "3", 0, 10), 3);
  EXPECT_EQ(*ParseWholeNumber("--omit", "+3", 0, 10), 3);
  EXPECT_EQ(*ParseWholeNumber("--x", "-2147483648"), -2147483648LL);
  EXPECT_THAT(ParseWholeNumber("--omit", "abc", 0, 10),
              StatusIs(kInvalid, Eq("--omit: \"abc\" is not a whole number")));
  EXPECT_THAT(ParseWholeNumber("--omit", "2.5", 0, 10),
              StatusIs(kInvalid, Eq("--omit: \"2.5\" is not a whole number")));
  EXPECT_THAT(ParseWholeNumber("--omit", "", 0, 10),
              StatusIs(kInvalid, Eq("--omit: \"\" is not a whole number")));
  EXPECT_THAT(ParseWholeNumber("--omit", " 3", 0, 10),
              StatusIs(kInvalid, Eq("--omit: \" 3\" is not a whole number")));
  EXPECT_THAT(ParseWholeNumber("--omit", "-1", 0, 10),
              StatusIs(kInvalid, Eq("--omit: -1 is too small: the smallest allowed is 0")));
  EXPECT_THAT(ParseWholeNumber("--omit", "11", 0, 10),
              StatusIs(kInvalid, Eq("--omit: 11 is too large: the largest allowed is 10")));
  EXPECT_THAT(ParseWholeNumber("--omit", "99999999999999999999999", 0, 10),
              StatusIs(kInvalid, Eq("--omit: 99999999999999999999999 is too large: a whole "
                                    "number from 0 to 10")));
  EXPECT_THAT(
      ParseWholeNumber("--on", "2147483648", 1, 2147483647),
      StatusIs(kInvalid, Eq("--on: 2147483648 is too large: the largest allowed is 2147483647")));
}

TEST(FlagValuesTest, SeedsAreNeverWrapped) {
  EXPECT_EQ(*ParseUnsigned64("--seed", "18446744073709551615"), 18446744073709551615ULL);
  EXPECT_EQ(*ParseUnsigned64("--seed", "0"), 0u);
  EXPECT_THAT(ParseUnsigned64("--seed", "-1"),
              StatusIs(kInvalid, Eq("--seed: -1 is negative: a whole number from 0 to "
                                    "18446744073709551615")));
  EXPECT_THAT(ParseUnsigned64("--seed", "18446744073709551616"),
              StatusIs(kInvalid, Eq("--seed: 18446744073709551616 is too large: a whole number "
                                    "from 0 to 18446744073709551615")));
  EXPECT_THAT(ParseUnsigned64("--seed", "0x10"),
              StatusIs(kInvalid, Eq("--seed: \"0x10\" is not a whole number")));
  EXPECT_THAT(ParseUnsigned64("--seed", "-x"),
              StatusIs(kInvalid, Eq("--seed: \"-x\" is not a whole number")));
}

TEST(FlagValuesTest, Numbers) {
  EXPECT_EQ(*ParseNumber("--tame", "1.5", AtLeast(1)), 1.5);
  EXPECT_EQ(*ParseNumber("--tame", ".5"), 0.5);
  EXPECT_EQ(*ParseNumber("--tame", "1e-3"), 0.001);
  EXPECT_THAT(ParseNumber("--tame", "x"), StatusIs(kInvalid, Eq("--tame: \"x\" is not a number")));
  EXPECT_THAT(ParseNumber("--tame", "1,5"),
              StatusIs(kInvalid, Eq("--tame: \"1,5\" is not a number")));
  EXPECT_THAT(ParseNumber("--tame", "0x1p3"),
              StatusIs(kInvalid, Eq("--tame: \"0x1p3\" is not a number")));
  EXPECT_THAT(ParseNumber("--tame", "nan"),
              StatusIs(kInvalid, Eq("--tame: \"nan\" is not a finite number")));
  EXPECT_THAT(ParseNumber("--tame", "-inf"),
              StatusIs(kInvalid, Eq("--tame: \"-inf\" is not a finite number")));
  EXPECT_THAT(ParseNumber("--tame", "1e999"),
              StatusIs(kInvalid, Eq("--tame: \"1e999\" is not a finite number")));
  EXPECT_THAT(ParseNumber("--tame", "0.5", AtLeast(1)),
              StatusIs(kInvalid, Eq("--tame: 0.5 is out of range: must be at least 1")));
  EXPECT_THAT(ParseNumber("--deadline", "0", Above(0)),
              StatusIs(kInvalid, Eq("--deadline: 0 is out of range: must be greater than 0")));
  EXPECT_THAT(ParseNumber("--mouth-mid-ratio", "1", OpenInterval(0, 1)),
              StatusIs(kInvalid, Eq("--mouth-mid-ratio: 1 is out of range: must be between 0 "
                                    "and 1 (both excluded)")));
  EXPECT_THAT(ParseNumber("--x", "11", NumberBounds{0, 10}),
              StatusIs(kInvalid, Eq("--x: 11 is out of range: must be from 0 to 10")));
}

TEST(FlagValuesTest, BoolsListsIntervals) {
  EXPECT_TRUE(*ParseBool("--x", "YES"));
  EXPECT_FALSE(*ParseBool("--x", "off"));
  EXPECT_THAT(ParseBool("--eyes-linked", "maybe"),
              StatusIs(kInvalid, Eq("--eyes-linked: \"maybe\" is not true or false")));
  EXPECT_THAT(ParseNumberList("--camera", "1,2,3", {}, 16),
              StatusIs(kInvalid, Eq("--camera: expected 16 comma-separated numbers, got 3")));
  EXPECT_THAT(ParseNumberList("--camera", "1,a"),
              StatusIs(kInvalid, Eq("--camera: \"a\" is not a number")));
  EXPECT_THAT(*ParseNumberList("--w", " 1, 2 "), ::testing::ElementsAre(1.0, 2.0));
  absl::StatusOr<FlagInterval> interval = ParseInterval("--speech", "10-25");
  ASSERT_THAT(interval, IsOk());
  EXPECT_EQ(interval->begin, 10);
  EXPECT_EQ(interval->end, 25);
  EXPECT_THAT(ParseInterval("--speech", "25-10"),
              StatusIs(kInvalid, Eq("--speech: \"25-10\": END must be greater than BEGIN")));
  EXPECT_THAT(ParseInterval("--speech", "10"),
              StatusIs(kInvalid, Eq("--speech: \"10\" is not a frame interval BEGIN-END (END one "
                                    "past the last frame, e.g. 10-25)")));
}

TEST(FlagValuesTest, ClosestMatch) {
  const std::vector<std::string> commands{"skeletal", "curves", "lipblink", "health"};
  EXPECT_EQ(ClosestMatch("skeletl", commands), "skeletal");
  EXPECT_EQ(ClosestMatch("curve", commands), "curves");
  EXPECT_EQ(ClosestMatch("lipsync", commands), "");
  EXPECT_EQ(ClosestMatch("helth", commands), "health");
  EXPECT_EQ(ClosestMatch("--omitt", {"--omit", "--on", "--output"}), "--omit");
  EXPECT_EQ(ClosestMatch("zzzzzz", commands), "");
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("", "abc"), 3);
}

TEST(FlagValuesTest, DescribeBounds) {
  EXPECT_EQ(DescribeBounds(AtLeast(0)), "at least 0");
  EXPECT_EQ(DescribeBounds(Above(0.5)), "greater than 0.5");
  EXPECT_EQ(DescribeBounds(NumberBounds{0, 0.5, false, true}), "at least 0 and less than 0.5");
  EXPECT_EQ(DescribeBounds({}), "any finite number");
}

}  // namespace
}  // namespace koma::client

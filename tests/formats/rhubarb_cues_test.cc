#include "formats/rhubarb_cues.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// Rhubarb's own JSON layout (rhubarb -f json), as it writes it.
constexpr char kJson[] = R"({
  "metadata": {
    "soundFile": "voice.wav",
    "duration": 1.25
  },
  "mouthCues": [
    { "start": 0.00, "end": 0.05, "value": "X" },
    { "start": 0.05, "end": 0.27, "value": "D" },
    { "start": 0.27, "end": 1.25, "value": "X" }
  ]
}
)";

TEST(RhubarbCuesTest, ReadsJson) {
  absl::StatusOr<std::vector<MouthCue>> cues = ParseRhubarbCues(kJson);
  ASSERT_TRUE(cues.ok()) << cues.status();
  ASSERT_EQ(cues->size(), 3u);
  EXPECT_EQ((*cues)[1].shape, 'D');
  EXPECT_EQ((*cues)[1].start_s, 0.05);
  EXPECT_EQ((*cues)[1].end_s, 0.27);
}

TEST(RhubarbCuesTest, ReadsTsvWithCrlfAndABom) {
  absl::StatusOr<std::vector<MouthCue>> cues =
      ParseRhubarbCues("\xEF\xBB\xBF" "0.00\tX\r\n0.05\tD\r\n0.27\tC\r\n1.25\tX\r\n");
  ASSERT_TRUE(cues.ok()) << cues.status();
  ASSERT_EQ(cues->size(), 4u);
  EXPECT_EQ((*cues)[2].shape, 'C');
  EXPECT_EQ((*cues)[2].end_s, 1.25);
  EXPECT_TRUE(std::isinf((*cues)[3].end_s));
}

TEST(RhubarbCuesTest, WritesWhatItReads) {
  const std::vector<MouthCue> cues = {{0, 0.125, 'X'}, {0.125, 0.25, 'C'}, {0.25, 1.0, 'A'}};
  absl::StatusOr<std::vector<MouthCue>> json = ParseRhubarbCues(WriteRhubarbJson(cues, 1.0, "v.wav"));
  ASSERT_TRUE(json.ok()) << json.status();
  ASSERT_EQ(json->size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ((*json)[i].start_s, cues[i].start_s);
    EXPECT_EQ((*json)[i].end_s, cues[i].end_s);
    EXPECT_EQ((*json)[i].shape, cues[i].shape);
  }
  EXPECT_EQ(WriteRhubarbTsv(cues), "0\tX\n0.125\tC\n0.25\tA\n1\tX\n");
  absl::StatusOr<std::vector<MouthCue>> tsv = ParseRhubarbCues(WriteRhubarbTsv(cues));
  ASSERT_TRUE(tsv.ok());
  EXPECT_EQ((*tsv)[2].end_s, 1.0);
}

TEST(RhubarbCuesTest, BadCuesNameTheirPlace) {
  EXPECT_THAT(ParseRhubarbCues("{\"mouthCues\": [{\"start\": 0, \"end\": 1, \"value\": \"Q\"}]}").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("mouthCues[0].value: \"Q\" is not one of A-H, X")));
  EXPECT_THAT(ParseRhubarbCues("{\"mouthCues\": [{\"start\": 1, \"end\": 0.5, \"value\": \"A\"}]}").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("mouthCues[0]: ends at 0.5")));
  EXPECT_THAT(ParseRhubarbCues("{\"mouthCues\": [{\"start\": 0, \"end\": 1, \"value\": \"A\"},"
                               "{\"start\": 0.5, \"end\": 2, \"value\": \"B\"}]}").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("mouthCues[1]: starts at 0.5")));
  EXPECT_THAT(ParseRhubarbCues("{\"mouthCues\": [{\"start\": -1, \"end\": 1, \"value\": \"A\"}]}").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("mouthCues[0].start: -1")));
  EXPECT_THAT(ParseRhubarbCues("{\"mouthCues\": 3}").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("mouthCues: missing")));
  EXPECT_THAT(ParseRhubarbCues("{").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("invalid JSON at byte ")));
  EXPECT_THAT(ParseRhubarbCues(std::string(100, '[')).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 1")));
  EXPECT_THAT(ParseRhubarbCues("{" + std::string(100, '[')).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("deeper than 32")));
  EXPECT_THAT(ParseRhubarbCues("0.00\tX\n0.5\tZ\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 2: \"Z\" is not one of")));
  EXPECT_THAT(ParseRhubarbCues("0.5\tA\n0.2\tB\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 2: starts at 0.2")));
  EXPECT_THAT(ParseRhubarbCues("0.5 A\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 1: expected TIME<tab>LETTER")));
  EXPECT_THAT(ParseRhubarbCues("x\tA\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 1:")));
  EXPECT_THAT(ParseRhubarbCues("\n\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("no mouth cues")));
}

}  // namespace
}  // namespace koma::formats

#include "formats/timing_sheet.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace koma::formats {
namespace {

using ::testing::EndsWith;
using ::testing::HasSubstr;

TEST(TimingSheetTest, NamesEveryFrameKind) {
  EXPECT_EQ(FrameKindName(FrameKind::kOriginal), "ORIGINAL");
  EXPECT_EQ(FrameKindName(FrameKind::kDuplicate), "DUPLICATE");
  EXPECT_EQ(FrameKindName(FrameKind::kHeld), "HELD");
}

TEST(TimingSheetTest, WritesOneRowPerOutputFrame) {
  TimingMap map;
  map.source_frames = {0, 2, 2, 3, 3};
  map.kinds = {FrameKind::kOriginal, FrameKind::kOriginal, FrameKind::kDuplicate,
               FrameKind::kOriginal, FrameKind::kHeld};
  map.deleted = {1};  // not part of the sheet
  EXPECT_EQ(WriteTimingSheetCsv(map, 0.0416667),
            "output_frame,source_frame,kind,time_s\n"
            "0,0,ORIGINAL,0\n"
            "1,2,ORIGINAL,0.0416667\n"
            "2,2,DUPLICATE,0.0833334\n"
            "3,3,ORIGINAL,0.1250001\n"
            "4,3,HELD,0.1666668\n");
}

TEST(TimingSheetTest, EmptyMapIsJustTheHeader) {
  EXPECT_EQ(WriteTimingSheetCsv(TimingMap{}, 0.04), "output_frame,source_frame,kind,time_s\n");
}

// Row t's time is t * frame_time, one multiplication, printed with 10 significant digits so
// binary noise (3 * 0.1 = 0.30000000000000004) does not reach the sheet.
TEST(TimingSheetTest, TimeIsMultipliedNeverAccumulated) {
  TimingMap map;
  for (int t = 0; t <= 1000; ++t) {
    map.source_frames.push_back(t);
    map.kinds.push_back(FrameKind::kOriginal);
  }
  const std::string csv = WriteTimingSheetCsv(map, 0.1);
  EXPECT_THAT(csv, HasSubstr("\n10,10,ORIGINAL,1\n"));
  EXPECT_THAT(csv, HasSubstr("\n3,3,ORIGINAL,0.3\n"));  // 3 * 0.1 = 0.30000000000000004
  EXPECT_THAT(csv, EndsWith("\n1000,1000,ORIGINAL,100\n"));
  EXPECT_EQ(csv.find('\r'), std::string::npos);
}

}  // namespace
}  // namespace koma::formats

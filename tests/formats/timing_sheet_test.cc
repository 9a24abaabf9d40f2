#include "formats/timing_sheet.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

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

// A BVH Frame Time is the rate rounded to 7 digits; within the film grid's 1e-4 the rate is
// recognised: the film's (timing_fps), else a whole number of frames per second.
TEST(TimingSheetTest, RecognisesTheRateWithinTheFilmGridsTolerance) {
  EXPECT_EQ(RecognisedFps(0.0416667, 24), 24);     // samples/pitch.bvh
  EXPECT_EQ(RecognisedFps(0.0416667, 0), 24);      // no film grid: the whole rate
  EXPECT_EQ(RecognisedFps(0.0083333, 24), 120);    // samples/mocap_120fps.bvh
  EXPECT_EQ(RecognisedFps(0.0333333, 24), 30);
  EXPECT_EQ(RecognisedFps(1.0 / 24, 24), 24);      // output at the timing rate
  EXPECT_EQ(RecognisedFps(1 / 23.976, 23.976), 23.976);
  EXPECT_EQ(RecognisedFps(0.0417, 24), 0);         // 23.98 fps: 8e-4 off 24
  EXPECT_EQ(RecognisedFps(1001.0 / 30000, 24), 0);  // 29.97 fps (NTSC): not a whole rate
  EXPECT_EQ(RecognisedFps(0.0, 24), 0);
}

// The case: samples/pitch.bvh (Frame Time 0.0416667, 24 fps) wrote 3 x 0.0416667 =
// 0.1250001 and 72 x 0.0416667 = 3.0000024; on the recognised rate the times are k / 24, in
// the shortest text that reads back to the same double.
TEST(TimingSheetTest, WritesExactTimesOnTheRecognisedRate) {
  TimingMap map;
  for (int t = 0; t <= 72; ++t) {
    map.source_frames.push_back(t);
    map.kinds.push_back(FrameKind::kOriginal);
  }
  const std::string csv = WriteTimingSheetCsv(map, 0.0416667, nullptr, 24);
  EXPECT_THAT(csv, HasSubstr("\n0,0,ORIGINAL,0\n"));
  EXPECT_THAT(csv, HasSubstr("\n1,1,ORIGINAL,0.041666666666666664\n"));  // 1 / 24
  EXPECT_THAT(csv, HasSubstr("\n3,3,ORIGINAL,0.125\n"));
  EXPECT_THAT(csv, HasSubstr("\n12,12,ORIGINAL,0.5\n"));
  EXPECT_THAT(csv, EndsWith("\n72,72,ORIGINAL,3\n"));
  // Every time reads back to exactly t / 24.
  size_t line_start = csv.find('\n') + 1;
  for (int t = 0; t <= 72; ++t) {
    const size_t line_end = csv.find('\n', line_start);
    const std::string line = csv.substr(line_start, line_end - line_start);
    const std::string time = line.substr(line.rfind(',') + 1);
    EXPECT_EQ(std::stod(time), static_cast<double>(t) / 24) << line;
    line_start = line_end + 1;
  }
  // With a film grid the time column keeps its place before grid_frame.
  TimingMap two;
  two.source_frames = {0, 0};
  two.kinds = {FrameKind::kOriginal, FrameKind::kHeld};
  const std::vector<int32_t> grid = {0, 0};
  EXPECT_EQ(WriteTimingSheetCsv(two, 0.0083333, &grid, 120),
            "output_frame,source_frame,kind,time_s,grid_frame\n"
            "0,0,ORIGINAL,0,0\n"
            "1,0,HELD,0.008333333333333333,0\n");
}

}  // namespace
}  // namespace koma::formats

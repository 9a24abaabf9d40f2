#include "formats/drawing_sheet.h"

#include <gtest/gtest.h>

namespace koma::formats {
namespace {

TEST(DrawingSheetTest, WritesOneRowPerOutputFrame) {
  DrawingTiming timing;
  timing.drawing_of_frame = {0, 0, 1, 1, 2};
  timing.source_frame = {0, 0, 2.5, 2.5, 4};
  EXPECT_EQ(WriteDrawingSheetCsv(timing, 24.0),
            "output_frame,drawing,source_frame,time_s\n"
            "0,0,0,0\n"
            "1,0,0,0.04166666667\n"
            "2,1,2.5,0.08333333333\n"
            "3,1,2.5,0.125\n"
            "4,2,4,0.1666666667\n");
}

TEST(DrawingSheetTest, EmptyTimingIsJustTheHeader) {
  EXPECT_EQ(WriteDrawingSheetCsv(DrawingTiming{}, 30.0),
            "output_frame,drawing,source_frame,time_s\n");
}

}  // namespace
}  // namespace koma::formats

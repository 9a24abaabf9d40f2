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

// One track per timing group: the default group's in the usual columns, then each group's.
TEST(DrawingSheetTest, GroupedSheetHasOneTrackPerGroup) {
  DrawingTiming body;
  body.drawing_of_frame = {0, 0, 0, 1};
  body.source_frame = {0, 0, 0, 3};
  DrawingTiming hair;
  hair.drawing_of_frame = {0, 0, 1, 2};
  hair.source_frame = {0, 0, 2, 3};
  EXPECT_EQ(WriteGroupedDrawingSheetCsv({{"body", &body}}, 24.0), WriteDrawingSheetCsv(body, 24.0));
  EXPECT_EQ(WriteGroupedDrawingSheetCsv({{"body", &body}, {"hair", &hair}}, 24.0),
            "output_frame,drawing,source_frame,time_s,hair_drawing,hair_source_frame\n"
            "0,0,0,0,0,0\n"
            "1,0,0,0.04166666667,0,0\n"
            "2,0,0,0.08333333333,1,2\n"
            "3,1,3,0.125,2,3\n");
}

}  // namespace
}  // namespace koma::formats

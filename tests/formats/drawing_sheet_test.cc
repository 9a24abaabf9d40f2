#include "formats/drawing_sheet.h"

#include <gtest/gtest.h>

namespace koma::formats {
namespace {

TEST(DrawingSheetTest, WritesOneRowPerOutputFrame) {
  DrawingTiming timing;
  timing.drawing_of_frame = {0, 0, 1, 1, 2};
  timing.source_frame = {0, 0, 2.5, 2.5, 4};
  EXPECT_EQ(WriteDrawingSheetCsv({"body", &timing, {}}, 24.0),
            "output_frame,drawing,source_frame,time_s,keys\n"
            "0,0,0,0,\n"
            "1,0,0,0.04166666667,\n"
            "2,1,2.5,0.08333333333,\n"
            "3,1,2.5,0.125,\n"
            "4,2,4,0.1666666667,\n");
}

TEST(DrawingSheetTest, EmptyTimingIsJustTheHeader) {
  const DrawingTiming empty;
  EXPECT_EQ(WriteDrawingSheetCsv({"body", &empty, {}}, 30.0),
            "output_frame,drawing,source_frame,time_s,keys\n");
}

// The keys each drawing carries, on the first frame that shows it; a drawing no frame shows
// (a grid drawing between two source frames) gives its keys to the next frame; an id with a
// comma is quoted.
TEST(DrawingSheetTest, KeysColumnNamesTheCurvesEachDrawingDraws) {
  DrawingTiming timing;
  timing.drawing_of_frame = {0, 0, 2, 2, 3};
  timing.source_frame = {0, 0, 2.5, 2.5, 4};
  const std::vector<std::vector<std::string>> keys = {
      {"ParamAngleX", "ParamBodyX"}, {"ParamArmL"}, {}, {"a,b"}};
  EXPECT_EQ(WriteDrawingSheetCsv({"body", &timing, keys}, 24.0),
            "output_frame,drawing,source_frame,time_s,keys\n"
            "0,0,0,0,ParamAngleX;ParamBodyX\n"
            "1,0,0,0.04166666667,\n"
            "2,2,2.5,0.08333333333,ParamArmL\n"
            "3,2,2.5,0.125,\n"
            "4,3,4,0.1666666667,\"a,b\"\n");
}

// One track per timing group: the default group's in the usual columns, then each group's.
TEST(DrawingSheetTest, GroupedSheetHasOneTrackPerGroup) {
  DrawingTiming body;
  body.drawing_of_frame = {0, 0, 0, 1};
  body.source_frame = {0, 0, 0, 3};
  DrawingTiming hair;
  hair.drawing_of_frame = {0, 0, 1, 2};
  hair.source_frame = {0, 0, 2, 3};
  EXPECT_EQ(WriteGroupedDrawingSheetCsv({{"body", &body, {}}}, 24.0),
            WriteDrawingSheetCsv({"body", &body, {}}, 24.0));
  EXPECT_EQ(WriteGroupedDrawingSheetCsv({{"body", &body, {{"x"}, {"x"}}}, {"hair", &hair, {{}, {"h"}, {}}}}, 24.0),
            "output_frame,drawing,source_frame,time_s,hair_drawing,hair_source_frame,keys\n"
            "0,0,0,0,0,0,x\n"
            "1,0,0,0.04166666667,0,0,\n"
            "2,0,0,0.08333333333,1,2,h\n"
            "3,1,3,0.125,2,3,x\n");
}

}  // namespace
}  // namespace koma::formats

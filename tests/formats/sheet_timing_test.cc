#include "formats/sheet_timing.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "formats/xdts.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::string Id() { return std::string(kXdtsIdentifier) + "\n"; }

// OpenToonz's exporter: no header, no subversion or options, one line, level names.
TEST(SheetTimingXdtsTest, ReadsCellTracksAndWarnsOfExtraTimeTables) {
  const std::string text = Id() + R"({"timeTables":[
    {"duration":5,"fields":[{"fieldId":0,"tracks":[{"trackNo":0,"frames":[
      {"frame":0,"data":[{"id":0,"values":["1"]}]},{"frame":2,"data":[{"id":0,"values":["4"]}]},
      {"frame":3,"data":[{"id":0,"values":["SYMBOL_NULL_CELL"]}]},
      {"frame":4,"data":[{"id":0,"values":["2"]}]},{"frame":5,"data":[{"id":0,"values":["SYMBOL_NULL_CELL"]}]}]}]}],
     "name":"cut","timeTableHeaders":[{"fieldId":0,"names":["pitch"]}]},
    {"duration":1,"name":"other","timeTableHeaders":[]}],"version":5})";
  ASSERT_OK_AND_ASSIGN(const SheetTiming sheet, ReadSheetTimingXdts(text));
  EXPECT_EQ(sheet.rows, 5);
  ASSERT_EQ(sheet.tracks.size(), 1u);
  EXPECT_EQ(sheet.tracks[0].name, "pitch");
  EXPECT_THAT(sheet.tracks[0].cells, ElementsAre("1", "1", "4", "", "2"));
  ASSERT_EQ(sheet.warnings.size(), 1u);
  EXPECT_EQ(sheet.warnings[0], "1 extra time table ignored: koma reads the first (\"cut\")");
}

TEST(SheetTimingCsvTest, ReadsSourceFramesAsOneBasedCells) {
  // A spreadsheet's save: BOM, CRLF, a row inserted without renumbering, a blank source.
  const std::string text =
      "\xEF\xBB\xBFoutput_frame,source_frame,kind,time_s\r\n0,0,ORIGINAL,0\r\n1,0,HELD,0.1\r\n"
      "1,7,HELD,0.1\r\n2,,ORIGINAL,0.2\r\n3, 2 ,ORIGINAL,0.3\r\n\r\n";
  ASSERT_OK_AND_ASSIGN(const SheetTiming sheet, ReadSheetTimingCsv(text));
  EXPECT_EQ(sheet.rows, 5);
  ASSERT_EQ(sheet.tracks.size(), 1u);
  EXPECT_EQ(sheet.tracks[0].name, "");
  EXPECT_THAT(sheet.tracks[0].cells, ElementsAre("1", "1", "8", "", "3"));
}

TEST(SheetTimingCsvTest, DrawingSheetReadsADrawingColumnPerGroup) {
  // koma curves --timing with a group "arms", saved by a spreadsheet: cells quoted, CRLF, a
  // row inserted, one drawing cell emptied; keys (last, quoted with a comma) ignored.
  const std::string text =
      "output_frame,drawing,source_frame,time_s,arms_drawing,arms_source_frame,keys\r\n"
      "\"0\",\"0\",\"0\",\"0\",\"0\",\"0\",\"a,b\"\r\n"
      "1,0,0,0.1,1,2.5,\r\n1,2,6,0.1,1,2.5,\r\n2,,,0.2, 3 ,7,\r\n";
  ASSERT_OK_AND_ASSIGN(const SheetTiming sheet, ReadSheetTimingCsv(text));
  EXPECT_EQ(sheet.kind, SheetKind::kDrawingCsv);
  EXPECT_EQ(sheet.rows, 4);
  ASSERT_EQ(sheet.tracks.size(), 2u);
  EXPECT_EQ(sheet.tracks[0].name, "drawing");
  EXPECT_THAT(sheet.tracks[0].cells, ElementsAre("1", "1", "3", ""));
  EXPECT_THAT(sheet.tracks[0].stated_source_frames, ElementsAre("0", "0", "6", ""));
  EXPECT_THAT(sheet.tracks[0].lines, ElementsAre(2, 3, 4, 5));
  EXPECT_EQ(sheet.tracks[1].name, "arms_drawing");
  EXPECT_THAT(sheet.tracks[1].cells, ElementsAre("1", "2", "2", "4"));
  EXPECT_THAT(sheet.tracks[1].stated_source_frames, ElementsAre("0", "2.5", "2.5", "7"));
  EXPECT_THAT(ReadSheetTimingCsv("output_frame,drawing,source_frame\n0,-1,0\n"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("line 2: drawing \"-1\" is not a whole number >= 0")));
  EXPECT_THAT(ReadSheetTimingCsv("output_frame,drawing,source_frame\n"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("no rows after the header")));
  ASSERT_OK_AND_ASSIGN(const SheetTiming skeletal,
                       ReadSheetTimingCsv("output_frame,source_frame\n0,\"4\"\n"));
  EXPECT_EQ(skeletal.kind, SheetKind::kSourceFrameCsv);
  EXPECT_THAT(skeletal.tracks[0].cells, ElementsAre("5"));
}

TEST(SheetTimingCsvTest, GridFramesAreTheRows) {
  // 120 fps on the 24 fps grid: five lines a grid frame; grid frame 3 named by no line.
  std::string text = "output_frame,source_frame,kind,time_s,grid_frame\n";
  const int grid[] = {0, 0, 1, 1, 2, 4, 4};
  const int source[] = {0, 0, 5, 5, 10, 20, 20};
  for (int i = 0; i < 7; ++i) {
    text += std::to_string(i) + "," + std::to_string(source[i]) + ",ORIGINAL,0," +
            std::to_string(grid[i]) + "\n";
  }
  ASSERT_OK_AND_ASSIGN(const SheetTiming sheet, ReadSheetTimingCsv(text));
  EXPECT_THAT(sheet.tracks[0].cells, ElementsAre("1", "6", "11", "11", "21"));
}

TEST(SheetTimingCsvTest, MalformedSheetsNameTheLine) {
  struct Case {
    std::string text;
    std::string message;
  };
  const Case cases[] = {
      {"", "no header line"},
      {"output_frame,kind\n0,HELD\n", "line 1: no source_frame column"},
      {"source_frame\n", "no rows after the header on line 1"},
      {"source_frame\n3\n-1\n", "line 3: source_frame \"-1\" is not a whole number >= 0"},
      {"source_frame\n2.5\n", "line 2: source_frame \"2.5\" is not a whole number"},
      {"source_frame,grid_frame\n1,2\n1,1\n", "line 3: grid_frame 1 comes after grid_frame 2"},
      {"source_frame,grid_frame\n1,0\n2,0\n", "line 3: grid_frame 0 shows source_frame 2 here"},
      {"source_frame,grid_frame\n1,x\n", "line 2: grid_frame \"x\" is not a whole number"},
  };
  for (const Case& c : cases) {
    EXPECT_THAT(ReadSheetTimingCsv(c.text).status(),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.text;
  }
  EXPECT_THAT(ReadSheetTimingCsv("source_frame\n1\n2\n3\n", 2).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("line 4: more than 2 rows")));
}

SheetTiming Tracks(const std::vector<std::string>& names) {
  SheetTiming sheet;
  for (const std::string& name : names) sheet.tracks.push_back({name, {}});
  return sheet;
}

TEST(MatchSheetTracksTest, ByNameThenByOrder) {
  // OpenToonz renames nothing; CSP or a hand edit may: unnamed ones go in order.
  ASSERT_OK_AND_ASSIGN(const std::vector<int> match,
                       MatchSheetTracks(Tracks({"x", "eyes", "y"}), {"mouth", "eyes", "brows"}));
  EXPECT_THAT(match, ElementsAre(0, 1, 2));
  ASSERT_OK_AND_ASSIGN(const std::vector<int> swapped,
                       MatchSheetTracks(Tracks({"eyes", "mouth"}), {"mouth", "eyes"}));
  EXPECT_THAT(swapped, ElementsAre(1, 0));
  // A proxy's sheet on the final rig: one track each, the names differ.
  ASSERT_OK_AND_ASSIGN(const std::vector<int> one, MatchSheetTracks(Tracks({"proxy"}), {"final"}));
  EXPECT_THAT(one, ElementsAre(0));
  EXPECT_THAT(MatchSheetTracks(Tracks({"pitch", "BG"}), {"pitch"}).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("track \"BG\" (Cell track 2 of 2): no such track: the clip's "
                                 "tracks are \"pitch\"")));
  EXPECT_THAT(MatchSheetTracks(Tracks({"eyes"}), {"mouth", "eyes"}).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("no track for \"mouth\"")));
}

TEST(SheetDrawingsTest, BlanksHoldTheDrawingBefore) {
  ASSERT_OK_AND_ASSIGN(const std::vector<int> drawings,
                       SheetDrawings({"t", {"", "3", "3", "", "", "007", "1"}}, 7, "1 to 7"));
  EXPECT_THAT(drawings, ElementsAre(2, 2, 2, 2, 2, 6, 0));
}

TEST(SheetDrawingsTest, CellsNamingNoDrawingAreErrorsNamingTrackFrameAndCell) {
  const char* bad[] = {"0", "8", "3a", "SYMBOL_TICK_3", "-1", "1234567890"};
  for (const char* cell : bad) {
    EXPECT_THAT(SheetDrawings({"pitch", {"1", "2", cell}}, 7, "source frames 1 to 7").status(),
                StatusIs(absl::StatusCode::kInvalidArgument,
                         HasSubstr(std::string("track \"pitch\", frame 3: cell \"") + cell +
                                   "\" names no drawing (cells are source frames 1 to 7)")))
        << cell;
  }
  EXPECT_THAT(SheetDrawings({"pitch", {"", ""}}, 7, "x").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("track \"pitch\": every one of its 2 frames is blank")));
}

// Property: a sheet koma writes (any cells 1..n, no blanks) reads back to the same cells,
// and its drawings are the cells minus one.
TEST(SheetTimingXdtsTest, KomaSheetsReadBackToTheirCells) {
  std::mt19937 random(46);
  for (int round = 0; round < 200; ++round) {
    XdtsSheet written;
    written.name = "clip";
    written.duration = 1 + static_cast<int>(random() % 40);
    const int drawings = 1 + static_cast<int>(random() % 30);
    const int tracks = 1 + static_cast<int>(random() % 3);
    for (int t = 0; t < tracks; ++t) {
      XdtsCellTrack track{"track " + std::to_string(t), {}};
      for (int r = 0; r < written.duration; ++r) {
        const bool hold = r > 0 && random() % 3 != 0;
        track.cells.push_back(hold ? track.cells.back() : std::to_string(1 + random() % drawings));
      }
      written.cell_tracks.push_back(std::move(track));
    }
    ASSERT_OK_AND_ASSIGN(const SheetTiming sheet, ReadSheetTimingXdts(WriteXdts(written)));
    ASSERT_EQ(sheet.rows, written.duration);
    ASSERT_EQ(sheet.tracks.size(), written.cell_tracks.size());
    std::vector<std::string> names;
    for (const XdtsCellTrack& track : written.cell_tracks) names.push_back(track.name);
    ASSERT_OK_AND_ASSIGN(const std::vector<int> match, MatchSheetTracks(sheet, names));
    for (size_t t = 0; t < sheet.tracks.size(); ++t) {
      EXPECT_EQ(match[t], static_cast<int>(t));
      EXPECT_EQ(sheet.tracks[t].cells, written.cell_tracks[t].cells);
      ASSERT_OK_AND_ASSIGN(const std::vector<int> read,
                           SheetDrawings(sheet.tracks[t], drawings, ""));
      for (size_t r = 0; r < read.size(); ++r) {
        EXPECT_EQ(read[r] + 1, std::stoi(written.cell_tracks[t].cells[r]));
      }
    }
    EXPECT_TRUE(sheet.warnings.empty());
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace koma::formats

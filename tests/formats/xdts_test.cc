#include "formats/xdts.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::testing::HasSubstr;

void ExpectSameSheet(const XdtsSheet& read, const XdtsSheet& written) {
  EXPECT_EQ(read.name, written.name);
  EXPECT_EQ(read.duration, written.duration);
  ASSERT_EQ(read.cell_tracks.size(), written.cell_tracks.size());
  for (size_t t = 0; t < read.cell_tracks.size(); ++t) {
    EXPECT_EQ(read.cell_tracks[t].name, written.cell_tracks[t].name) << "track " << t;
    EXPECT_EQ(read.cell_tracks[t].cells, written.cell_tracks[t].cells) << "track " << t;
  }
  std::vector<const XdtsDialogTrack*> with_lines;
  for (const XdtsDialogTrack& track : written.dialog_tracks) {
    if (!track.lines.empty()) with_lines.push_back(&track);
  }
  ASSERT_EQ(read.dialog_tracks.size(), with_lines.size());
  for (size_t t = 0; t < with_lines.size(); ++t) {
    EXPECT_EQ(read.dialog_tracks[t].name, with_lines[t]->name);
    EXPECT_TRUE(read.dialog_tracks[t].lines == with_lines[t]->lines) << "dialog track " << t;
  }
}

TEST(XdtsWriterTest, HandWrittenSheetGivesTheseBytes) {
  XdtsSheet sheet;
  sheet.name = "pitch";
  sheet.duration = 5;
  sheet.cell_tracks.push_back({"pitch", {"1", "1", "2", "", "3"}});
  sheet.dialog_tracks.push_back({"voice", {{1, 3, "pitch", "speech 1"}}});
  const std::string expected = R"(exchangeDigitalTimeSheet Save Data
{
  "timeTables": [
    {
      "duration": 5,
      "fields": [
        {
          "fieldId": 0,
          "tracks": [
            {
              "frames": [
                {"data": [{"id": 0, "values": ["1"]}], "frame": 0},
                {"data": [{"id": 0, "values": ["2"]}], "frame": 2},
                {"data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}], "frame": 3},
                {"data": [{"id": 0, "values": ["3"]}], "frame": 4},
                {"data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}], "frame": 5}
              ],
              "trackNo": 0
            }
          ]
        },
        {
          "fieldId": 3,
          "tracks": [
            {
              "frames": [
                {"data": [{"id": 0, "values": ["pitch", "speech 1"]}], "frame": 1},
                {"data": [{"id": 0, "values": ["SYMBOL_HYPHEN"]}], "frame": 2}
              ],
              "trackNo": 0
            }
          ]
        }
      ],
      "name": "pitch",
      "timeTableHeaders": [
        {"fieldId": 0, "names": ["pitch"]},
        {"fieldId": 3, "names": ["voice"]}
      ]
    }
  ],
  "version": 5
}
)";
  EXPECT_EQ(WriteXdts(sheet), expected);
  ASSERT_OK_AND_ASSIGN(const XdtsSheet read, ReadXdts(expected));
  ExpectSameSheet(read, sheet);
}

TEST(XdtsWriterTest, NamesToolsChokeOnAreValidJsonAndReadBackEqual) {
  XdtsSheet sheet;
  sheet.name = "カット\"12\"\n\\";
  sheet.duration = 2;
  sheet.cell_tracks.push_back({"口パク \"A\"\t\x01\x1f end", {"1", "2"}});
  sheet.cell_tracks.push_back({"目\r\nパチ / eyes", {"1", "1"}});
  sheet.dialog_tracks.push_back({"台詞", {{0, 2, "ハルカ", "「こんにちは」\n\"hi\""}}});
  const std::string text = WriteXdts(sheet);
  EXPECT_THAT(text, HasSubstr(R"("口パク \"A\"\t\u0001\u001f end")"));
  EXPECT_THAT(text, HasSubstr(R"("カット\"12\"\n\\")"));
  ASSERT_OK_AND_ASSIGN(const XdtsSheet read, ReadXdts(text));
  ExpectSameSheet(read, sheet);
}

TEST(XdtsWriterTest, InvalidUtf8BecomesReplacementCharacter) {
  XdtsSheet sheet;
  sheet.name = "bad\xff";
  sheet.duration = 1;
  sheet.cell_tracks.push_back({"x\xc3", {"1"}});
  ASSERT_OK_AND_ASSIGN(const XdtsSheet read, ReadXdts(WriteXdts(sheet)));
  EXPECT_EQ(read.name, "bad\xEF\xBF\xBD");
  EXPECT_EQ(read.cell_tracks[0].name, "x\xEF\xBF\xBD");
}

// Random sheets: reading a written sheet gives it back, and writing is deterministic.
TEST(XdtsPropertyTest, WriteThenReadGivesTheSheet) {
  std::mt19937 random(20181129);
  const std::vector<std::string> alphabet = {"", "1", "2", "3", "10", "12a", "名"};
  for (int round = 0; round < 300; ++round) {
    XdtsSheet sheet;
    sheet.name = "sheet " + std::to_string(round);
    sheet.duration = 1 + static_cast<int>(random() % 200);
    const int tracks = 1 + static_cast<int>(random() % 4);
    for (int t = 0; t < tracks; ++t) {
      XdtsCellTrack track{"layer " + std::to_string(t), {}};
      std::string cell = alphabet[random() % alphabet.size()];
      for (int r = 0; r < sheet.duration; ++r) {
        if (random() % 3 == 0) cell = alphabet[random() % alphabet.size()];
        track.cells.push_back(cell);
      }
      sheet.cell_tracks.push_back(std::move(track));
    }
    const int dialog_tracks = static_cast<int>(random() % 3);
    for (int t = 0; t < dialog_tracks; ++t) {
      XdtsDialogTrack track{"speech " + std::to_string(t), {}};
      int row = static_cast<int>(random() % 5);
      while (row < sheet.duration) {
        const int end = std::min(sheet.duration, row + 1 + static_cast<int>(random() % 9));
        track.lines.push_back({row, end, "A", "line " + std::to_string(row)});
        row = end + static_cast<int>(random() % 7);  // adjacent lines too (gap 0)
      }
      sheet.dialog_tracks.push_back(std::move(track));
    }
    const std::string text = WriteXdts(sheet);
    EXPECT_EQ(text, WriteXdts(sheet));
    ASSERT_OK_AND_ASSIGN(const XdtsSheet read, ReadXdts(text));
    ExpectSameSheet(read, sheet);
    if (HasFailure()) return;
  }
}

// A file as CLIP STUDIO PAINT or OpenToonz may write it, read by OpenToonz's rules.
TEST(XdtsReaderTest, FollowsOpenToonzImportRules) {
  const std::string text =
      "\xEF\xBB\xBF" "exchangeDigitalTimeSheet Save Data\r\n"
      R"({"version": 5, "header": {"cut": "1", "scene": "1"}, "timeTables": [{
        "name": "cut1", "duration": 12,
        "timeTableHeaders": [{"fieldId": 5, "names": ["cam"]}, {"fieldId": 0, "names": ["A", "B", "C"]}],
        "fields": [
          {"fieldId": 5, "tracks": [{"trackNo": 0, "frames": [{"frame": 0, "data": [{"id": 0, "values": ["PAN"]}]}]}]},
          {"fieldId": 0, "tracks": [
            {"trackNo": 0, "frames": [
              {"frame": 6, "data": [{"id": 0, "values": ["SYMBOL_TICK_1"]}]},
              {"frame": 2, "data": [{"id": 0, "values": ["1"]}]},
              {"frame": 4, "data": [{"id": 0, "values": ["SYMBOL_HYPHEN"]}]},
              {"frame": 5, "data": [{"id": 0, "values": ["2"]}]},
              {"frame": 8, "data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}]},
              {"frame": 10, "data": [{"id": 0, "values": ["3"]}]}]},
            {"trackNo": 2, "frames": [
              {"frame": 0, "data": [{"id": 0, "values": ["5"]}]},
              {"frame": 3, "data": [{"id": 0, "values": ["SYMBOL_NULL_CELL"]}]},
              {"frame": 12, "data": [{"id": 0, "values": ["7"]}]}]}]}]}]})";
  ASSERT_OK_AND_ASSIGN(const XdtsSheet sheet, ReadXdts(text));
  EXPECT_EQ(sheet.name, "cut1");
  EXPECT_EQ(sheet.duration, 12);
  ASSERT_EQ(sheet.cell_tracks.size(), 2u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "A");
  // Empty before the first entry; gaps repeat; hyphen and tick repeat; null empties; the last
  // cell runs to the end.
  EXPECT_EQ(sheet.cell_tracks[0].cells,
            (std::vector<std::string>{"", "", "1", "1", "1", "2", "2", "2", "", "", "3", "3"}));
  EXPECT_EQ(sheet.cell_tracks[1].name, "C");
  // An entry at the duration only closes; the empty last cell is not continued.
  EXPECT_EQ(sheet.cell_tracks[1].cells,
            (std::vector<std::string>{"5", "5", "5", "", "", "", "", "", "", "", "", ""}));
  EXPECT_TRUE(sheet.dialog_tracks.empty());
}

TEST(XdtsReaderTest, DialogLinesEndAtTheirLastHyphen) {
  const std::string text = std::string(kXdtsIdentifier) + "\n" + R"({"version": 5, "timeTables": [{
      "name": "", "duration": 10,
      "timeTableHeaders": [{"fieldId": 3, "names": ["S1"]}],
      "fields": [{"fieldId": 3, "tracks": [{"trackNo": 0, "frames": [
        {"frame": 1, "data": [{"id": 0, "values": ["A", "hello"]}]},
        {"frame": 2, "data": [{"id": 0, "values": ["SYMBOL_HYPHEN"]}]},
        {"frame": 3, "data": [{"id": 0, "values": ["SYMBOL_HYPHEN"]}]},
        {"frame": 6, "data": [{"id": 0, "values": ["B"]}]}]}]}]}]})";
  ASSERT_OK_AND_ASSIGN(const XdtsSheet sheet, ReadXdts(text));
  ASSERT_EQ(sheet.dialog_tracks.size(), 1u);
  EXPECT_EQ(sheet.dialog_tracks[0].name, "S1");
  ASSERT_EQ(sheet.dialog_tracks[0].lines.size(), 2u);
  EXPECT_TRUE(sheet.dialog_tracks[0].lines[0] == (XdtsDialogLine{1, 4, "A", "hello"}));
  EXPECT_TRUE(sheet.dialog_tracks[0].lines[1] == (XdtsDialogLine{6, 7, "B", ""}));
}

TEST(XdtsReaderTest, MalformedFilesNameTheLineOrPath) {
  const std::string id = std::string(kXdtsIdentifier) + "\n";
  const std::string table = R"("timeTables": [{"name": "", "duration": 3, "timeTableHeaders": [],
      "fields": [{"fieldId": 0, "tracks": [{"trackNo": 0, "frames": [)";
  struct Case {
    std::string text;
    std::string message;
  };
  const Case cases[] = {
      {"{\"version\": 5}", "line 1: expected \"exchangeDigitalTimeSheet Save Data\""},
      {"toeiDigitalTimeSheet Save Data\n{}", "line 1: expected"},
      {id + "{\"version\": 5,", "line 2 on: invalid JSON"},
      {id + "{\"version\": 4, \"timeTables\": []}", "version: 4 is not 5"},
      {id + "{\"version\": 5}", "missing \"timeTables\""},
      {id + "{\"version\": 5, \"timeTables\": []}", "timeTables: expected at least one"},
      {id + R"({"version": 5, "timeTables": [{"name": "", "duration": 0, "timeTableHeaders": []}]})",
       "timeTables[0].duration: 0 must be >= 1"},
      {id + R"({"version": 5, "timeTables": [{"name": "", "duration": 99999999, "timeTableHeaders": []}]})",
       "timeTables[0].duration: 99999999 must be <= 16777216"},
      {id + R"({"version": 5, "timeTables": [{"name": "", "duration": 1.5, "timeTableHeaders": []}]})",
       "timeTables[0].duration: expected a whole number, got 1.5"},
      {id + "{\"version\": 5, " + table +
           R"({"frame": -2, "data": [{"id": 0, "values": ["1"]}]}]}]}]}]})",
       "timeTables[0].fields[0].tracks[0].frames[0].frame: -2 must be >= 0"},
      {id + "{\"version\": 5, " + table + R"({"frame": 0, "data": [{"id": 0, "values": [1]}]}]}]}]}]})",
       "timeTables[0].fields[0].tracks[0].frames[0].data[0].values[0]: expected a string, got 1"},
      {id + "{\"version\": 5, " + table + R"({"frame": 0, "data": []}]}]}]}]})",
       "timeTables[0].fields[0].tracks[0].frames[0].data: expected at least one instruction"},
      {id + std::string(100, '[') + std::string(100, ']'), "nested deeper than 64"},
  };
  for (const Case& c : cases) {
    const absl::StatusOr<XdtsSheet> sheet = ReadXdts(c.text);
    EXPECT_FALSE(sheet.ok()) << c.text;
    if (!sheet.ok()) {
      EXPECT_EQ(sheet.status().code(), absl::StatusCode::kInvalidArgument);
      EXPECT_THAT(std::string(sheet.status().message()), HasSubstr(c.message)) << c.text;
    }
  }
}

TEST(XdtsReaderTest, TrackLimitIsEnforced) {
  XdtsSheet sheet;
  sheet.duration = 1;
  for (int t = 0; t < 5; ++t) sheet.cell_tracks.push_back({"t", {"1"}});
  XdtsReadLimits limits;
  limits.max_tracks = 4;
  const absl::StatusOr<XdtsSheet> read = ReadXdts(WriteXdts(sheet), limits);
  ASSERT_FALSE(read.ok());
  EXPECT_THAT(std::string(read.status().message()),
              HasSubstr("timeTables[0].fields[0].tracks: 5 tracks is over the limit of 4"));
}

}  // namespace
}  // namespace koma::formats

#include "client/xdts_sheets.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::testing::ElementsAre;
using ::testing::ElementsAreArray;

std::vector<std::string> Cells(std::initializer_list<int> numbers) {
  std::vector<std::string> out;
  for (int n : numbers) out.push_back(n == 0 ? "" : std::to_string(n));
  return out;
}

TEST(XdtsClipNameTest, FileNameWithoutFolderAndExtension) {
  EXPECT_EQ(XdtsClipName("samples/pitch.bvh", "out/x.xdts"), "pitch");
  EXPECT_EQ(XdtsClipName("a/talk.motion3.json", ""), "talk");
  EXPECT_EQ(XdtsClipName("a/arm.CSV", ""), "arm");
  EXPECT_EQ(XdtsClipName("-", "out/sheet.xdts"), "sheet");
  EXPECT_EQ(XdtsClipName("-", "-"), "koma");
  EXPECT_EQ(XdtsClipName("カット1.bvh", ""), "カット1");
  // A voice alone names the sheet after its recording or cues.
  EXPECT_EQ(XdtsClipName("rec/line_042.WAV", "x.xdts"), "line_042");
  EXPECT_EQ(XdtsClipName("line.cues.tsv", ""), "line.cues");
  EXPECT_EQ(XdtsClipName("take.opus", ""), "take");
  // Every input format's extension, from the format table (an FBX take was "take.fbx").
  EXPECT_EQ(XdtsClipName("mocap/take.FBX", ""), "take");
  EXPECT_EQ(XdtsClipName("wave.glb", ""), "wave");
  EXPECT_EQ(XdtsClipName(".bvh", "out/s.xdts"), ".bvh");  // nothing before the extension
}

TEST(SkeletalXdtsSheetTest, CellsAreTheSourceFramesCountedFromOne) {
  v1::RetimeSkeletalResponse response;
  for (int s : {0, 0, 0, 1, 1, 1, 3, 3, 3, 5}) response.add_source_frames(s);
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, SkeletalXdtsSheet(response, "pitch"));
  EXPECT_EQ(sheet.name, "pitch");
  EXPECT_EQ(sheet.duration, 10);
  ASSERT_EQ(sheet.cell_tracks.size(), 1u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "pitch");
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 1, 1, 2, 2, 2, 4, 4, 4, 6})));
}

TEST(SkeletalXdtsSheetTest, GridRowsFromTheOutputFramesGridFrames) {
  // 120 fps source: five output frames per grid frame.
  v1::RetimeSkeletalResponse response;
  response.set_timing_fps(24);
  const int grid_source[] = {0, 0, 10, 15};  // the drawing of grid frames 0..3
  for (int t = 0; t < 16; ++t) {
    const int g = t / 5;
    response.add_grid_frames(g);
    response.add_source_frames(grid_source[g]);
  }
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, SkeletalXdtsSheet(response, "mocap"));
  EXPECT_EQ(sheet.duration, 4);
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 1, 11, 16})));
}

TEST(SkeletalXdtsSheetTest, GridFramesNoOutputFrameShowsRepeatTheRowBefore) {
  // A 12 fps source on the 24 fps grid: output frame k shows grid frame 2k.
  v1::RetimeSkeletalResponse response;
  response.set_timing_fps(24);
  for (int k = 0; k < 4; ++k) {
    response.add_grid_frames(2 * k);
    response.add_source_frames(k == 1 ? 0 : k);
  }
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, SkeletalXdtsSheet(response, "slow"));
  EXPECT_EQ(sheet.duration, 7);
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 1, 1, 1, 3, 3, 4})));
}

TEST(SkeletalXdtsSheetTest, EmptyAnswerIsAnError) {
  EXPECT_FALSE(SkeletalXdtsSheet(v1::RetimeSkeletalResponse(), "x").ok());
}

v1::RetimeCurvesResponse TwoTimings(bool grid) {
  v1::RetimeCurvesResponse response;
  if (grid) response.set_timing_fps(24);
  v1::DrawingTiming* threes = response.add_timings();
  threes->set_frames_per_drawing(3);
  for (int d : {0, 0, 0, 1, 1, 1, 2}) threes->add_drawing_of_frame(d);
  for (int g : {0, 3, 5}) threes->add_drawing_start_grid(g);
  v1::DrawingTiming* twos = response.add_timings();
  twos->set_frames_per_drawing(2);
  for (int d : {0, 0, 1, 1, 2, 2, 3}) twos->add_drawing_of_frame(d);
  for (int g : {0, 2, 4, 5}) twos->add_drawing_start_grid(g);
  for (const auto& [id, timing] : std::vector<std::pair<std::string, int>>{
           {"ParamAngleX", 1}, {"ParamAngleY", 0}, {"ParamHair", 1}}) {
    v1::RetimedCurve* curve = response.add_curves();
    curve->set_id(id);
    curve->set_timing(timing);
  }
  return response;
}

TEST(CurvesXdtsSheetTest, OneTrackPerTimingNamedByItsCurves) {
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, CurvesXdtsSheet(TwoTimings(false), "arm"));
  EXPECT_EQ(sheet.duration, 7);
  ASSERT_EQ(sheet.cell_tracks.size(), 2u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "ParamAngleY (on 3)");
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 1, 1, 2, 2, 2, 3})));
  EXPECT_EQ(sheet.cell_tracks[1].name, "ParamAngleX, ParamHair (on 2)");
  EXPECT_THAT(sheet.cell_tracks[1].cells, ElementsAreArray(Cells({1, 1, 2, 2, 3, 3, 4})));
}

TEST(CurvesXdtsSheetTest, GridRowsFromTheDrawingsStartGridFrames) {
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, CurvesXdtsSheet(TwoTimings(true), "arm"));
  EXPECT_EQ(sheet.duration, 6);  // the last drawing starts on grid frame 5
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 1, 1, 2, 2, 3})));
  EXPECT_THAT(sheet.cell_tracks[1].cells, ElementsAreArray(Cells({1, 1, 2, 2, 3, 4})));
}

TEST(CurvesXdtsSheetTest, ATimingWithNoCurveHasNoTrackAndOneTrackTakesTheClipName) {
  v1::RetimeCurvesResponse response = TwoTimings(false);
  response.mutable_curves(1)->set_timing(1);  // every curve on twos
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, CurvesXdtsSheet(response, "arm"));
  ASSERT_EQ(sheet.cell_tracks.size(), 1u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "arm (on 2)");
}

TEST(CurvesXdtsSheetTest, TimingGroupsNameTheirTracks) {
  // Three timings: body's (ParamAngleY, on 3), face's (ParamAngleX, on 2), and a curve
  // override inside face (ParamHair, on 3 again); plus an empty group with no timing.
  v1::RetimeCurvesResponse response = TwoTimings(false);
  *response.add_timings() = response.timings(0);
  response.mutable_curves(2)->set_timing(2);
  v1::CurveTimingGroupResult* body = response.add_timing_groups();
  body->set_name("body");
  body->add_curves(1);
  body->set_timing(0);
  v1::CurveTimingGroupResult* face = response.add_timing_groups();
  face->set_name("face");
  face->add_curves(0);
  face->add_curves(2);
  face->set_timing(1);
  v1::CurveTimingGroupResult* hair = response.add_timing_groups();
  hair->set_name("hair");
  hair->set_timing(-1);
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, CurvesXdtsSheet(response, "talk"));
  ASSERT_EQ(sheet.cell_tracks.size(), 3u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "body (on 3)");
  EXPECT_EQ(sheet.cell_tracks[1].name, "face (on 2)");
  EXPECT_EQ(sheet.cell_tracks[2].name, "face: ParamHair (on 3)");
  EXPECT_THAT(sheet.cell_tracks[2].cells, ElementsAreArray(Cells({1, 1, 1, 2, 2, 2, 3})));
  // One group with curves still names its one track (the drawing sheet's column).
  response.mutable_curves(0)->set_timing(0);
  response.mutable_curves(2)->set_timing(0);
  response.mutable_timing_groups(0)->add_curves(0);
  response.mutable_timing_groups(0)->add_curves(2);
  response.mutable_timing_groups(1)->clear_curves();
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet one, CurvesXdtsSheet(response, "talk"));
  ASSERT_EQ(one.cell_tracks.size(), 1u);
  EXPECT_EQ(one.cell_tracks[0].name, "body (on 3)");
}

v1::LipBlinkResponse LipBlinkAnswer() {
  v1::LipBlinkResponse response;
  v1::MouthTrack* mouth = response.add_mouths();
  mouth->set_id("ParamMouthOpenY");
  mouth->set_closed_level(0);
  mouth->set_mid_level(0.5);
  mouth->set_open_level(1);
  v1::FrameInterval* speech = mouth->add_speech();
  speech->set_begin(2);
  speech->set_end(7);
  for (const auto& [begin, length, shape] :
       std::vector<std::tuple<int, int, v1::MouthShape>>{{2, 3, v1::MOUTH_OPEN}, {5, 2, v1::MOUTH_MID}}) {
    v1::MouthHold* hold = mouth->add_holds();
    hold->set_begin(begin);
    hold->set_length(length);
    hold->set_shape(shape);
  }
  for (const char* id : {"ParamEyeLOpen", "ParamEyeROpen"}) {
    v1::EyeTrack* eye = response.add_eyes();
    eye->set_id(id);
    eye->set_closed_level(0);
    eye->set_mid_level(0.5);
    eye->set_open_level(1);
    v1::Blink* blink = eye->add_blinks();
    blink->set_closing_begin(2);
    blink->set_closed_begin(4);
    blink->set_closed_end(4);
    blink->set_open_span(3);
    blink->set_hold(2);
  }
  // Converted values: outside speech the mouth keeps its input (0.9 at frame 10: open).
  const std::vector<double> mouth_values = {0, 0, 1, 1, 1, 0.5, 0.5, 0, 0, 0, 0.9, 0.2};
  const std::vector<double> eye_values = {1, 1, 1, 1, 0, 0, 0.5, 0.5, 1, 0.7, 0.3, 1};
  for (const auto& [id, values] : std::vector<std::pair<std::string, std::vector<double>>>{
           {"ParamMouthOpenY", mouth_values},
           {"ParamEyeLOpen", eye_values},
           {"ParamEyeROpen", eye_values}}) {
    v1::ConvertedCurve* curve = response.add_curves();
    curve->set_id(id);
    for (double v : values) curve->add_values(v);
  }
  return response;
}

TEST(LipBlinkXdtsSheetTest, MouthEyesAndSpeech) {
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet,
                       LipBlinkXdtsSheet(LipBlinkAnswer(), 30, "talk"));
  EXPECT_EQ(sheet.duration, 12);
  ASSERT_EQ(sheet.cell_tracks.size(), 2u);
  EXPECT_EQ(sheet.cell_tracks[0].name, "ParamMouthOpenY (1 closed, 2 mid, 3 open)");
  EXPECT_THAT(sheet.cell_tracks[0].cells,
              ElementsAreArray(Cells({1, 1, 3, 3, 3, 2, 2, 1, 1, 1, 3, 1})));
  // Linked eyes: one track. Closing phase 2-3 open, closed 4-5 (k = 2), half 6-7, open 8;
  // after the blink the input: 0.7 -> half (nearer 0.5), 0.3 -> half, 1 -> open.
  EXPECT_EQ(sheet.cell_tracks[1].name, "ParamEyeLOpen, ParamEyeROpen (1 open, 2 half, 3 closed)");
  EXPECT_THAT(sheet.cell_tracks[1].cells,
              ElementsAreArray(Cells({1, 1, 1, 1, 3, 3, 2, 2, 1, 2, 2, 1})));
  ASSERT_EQ(sheet.dialog_tracks.size(), 1u);
  EXPECT_EQ(sheet.dialog_tracks[0].name, "ParamMouthOpenY speech");
  ASSERT_EQ(sheet.dialog_tracks[0].lines.size(), 1u);
  EXPECT_EQ(sheet.dialog_tracks[0].lines[0].begin, 2);
  EXPECT_EQ(sheet.dialog_tracks[0].lines[0].end, 7);
  EXPECT_EQ(sheet.dialog_tracks[0].lines[0].speaker, "talk");
  EXPECT_EQ(sheet.dialog_tracks[0].lines[0].text, "speech 1");
}

TEST(LipBlinkXdtsSheetTest, UnlinkedEyesWithOtherCellsGetTracksOfTheirOwn) {
  v1::LipBlinkResponse response = LipBlinkAnswer();
  response.mutable_eyes(1)->clear_blinks();
  response.mutable_curves(2)->clear_values();
  for (int f = 0; f < 12; ++f) response.mutable_curves(2)->add_values(1);
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, LipBlinkXdtsSheet(response, 30, "talk"));
  ASSERT_EQ(sheet.cell_tracks.size(), 3u);
  EXPECT_EQ(sheet.cell_tracks[2].name, "ParamEyeROpen (1 open, 2 half, 3 closed)");
  EXPECT_THAT(sheet.cell_tracks[2].cells, ElementsAreArray(Cells({1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1})));
}

TEST(LipBlinkXdtsSheetTest, GridRowsAreTheClipsGridFrames) {
  // 12 source frames at 48 fps on the 24 fps grid: grid frames 0..5, frame 2g sampled.
  v1::LipBlinkResponse response = LipBlinkAnswer();
  response.set_timing_fps(24);
  response.mutable_mouths(0)->clear_holds();
  response.mutable_mouths(0)->clear_speech();
  response.mutable_eyes(0)->clear_blinks();
  response.mutable_eyes(1)->clear_blinks();
  ASSERT_OK_AND_ASSIGN(const formats::XdtsSheet sheet, LipBlinkXdtsSheet(response, 48, "talk"));
  EXPECT_EQ(sheet.duration, 6);
  // Mouth values at frames 0, 2, 4, 6, 8, 10: 0, 1, 1, 0.5, 0, 0.9.
  EXPECT_THAT(sheet.cell_tracks[0].cells, ElementsAreArray(Cells({1, 3, 3, 2, 1, 3})));
  EXPECT_TRUE(sheet.dialog_tracks.size() == 1 && sheet.dialog_tracks[0].lines.empty());
}

}  // namespace
}  // namespace koma::client

#include "core/mouth_cues.h"

#include <gtest/gtest.h>

#include <limits>

namespace koma {
namespace {

TEST(MouthCuesTest, LettersMapToThreeDrawings) {
  EXPECT_EQ(AnimeShapeOfCue('A'), MouthShape::kClosed);
  EXPECT_EQ(AnimeShapeOfCue('B'), MouthShape::kClosed);
  EXPECT_EQ(AnimeShapeOfCue('G'), MouthShape::kClosed);
  for (char c : {'C', 'E', 'F', 'H'}) EXPECT_EQ(AnimeShapeOfCue(c), MouthShape::kMid) << c;
  EXPECT_EQ(AnimeShapeOfCue('D'), MouthShape::kOpen);
  for (MouthShape s : {MouthShape::kClosed, MouthShape::kMid, MouthShape::kOpen}) {
    EXPECT_EQ(AnimeShapeOfCue(CueOfAnimeShape(s)), s);  // koma's letters read back
  }
}

TEST(MouthCuesTest, CuesSampledAtFrameTimes) {
  // At 10 fps: frames at 0, 0.1, ... Cue D 0.05-0.25 covers frames 1, 2; B 0.25-0.32 covers
  // 3; a C shorter than a frame (0.32-0.38) covers none; X from 0.38; D again from 0.6 to inf.
  const std::vector<MouthCue> cues = {{0.0, 0.05, 'X'},  {0.05, 0.25, 'D'},
                                      {0.25, 0.32, 'B'}, {0.32, 0.38, 'C'},
                                      {0.38, 0.6, 'X'},  {0.6, std::numeric_limits<double>::infinity(), 'D'}};
  const VoiceActivity v = CuesOnFrames(cues, 10, 9);
  ASSERT_EQ(v.speech.size(), 2u);
  EXPECT_EQ(v.speech[0], (FrameInterval{1, 4}));
  EXPECT_EQ(v.speech[1], (FrameInterval{6, 9}));
  EXPECT_EQ(v.follow[0], MouthShape::kClosed);
  EXPECT_EQ(v.follow[1], MouthShape::kOpen);
  EXPECT_EQ(v.follow[2], MouthShape::kOpen);
  EXPECT_EQ(v.follow[3], MouthShape::kClosed);
  EXPECT_EQ(v.follow[6], MouthShape::kOpen);
}

TEST(MouthCuesTest, HoldsBecomeCuesWithXBetween) {
  const std::vector<MouthHold> holds = {{2, 3, MouthShape::kMid}, {5, 1, MouthShape::kOpen},
                                        {10, 2, MouthShape::kClosed}};
  const std::vector<MouthCue> cues = CuesOfHolds(holds, 10, 2.0);
  ASSERT_EQ(cues.size(), 6u);
  EXPECT_EQ(cues[0].shape, 'X');
  EXPECT_DOUBLE_EQ(cues[0].end_s, 0.2);
  EXPECT_EQ(cues[1].shape, 'C');
  EXPECT_DOUBLE_EQ(cues[1].end_s, 0.5);
  EXPECT_EQ(cues[2].shape, 'D');
  EXPECT_EQ(cues[3].shape, 'X');
  EXPECT_EQ(cues[4].shape, 'A');
  EXPECT_EQ(cues[5].shape, 'X');
  EXPECT_DOUBLE_EQ(cues[5].end_s, 2.0);
  for (size_t i = 1; i < cues.size(); ++i) EXPECT_EQ(cues[i].start_s, cues[i - 1].end_s);
}

}  // namespace
}  // namespace koma

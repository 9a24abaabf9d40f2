// MouthDrawings / BlinkDrawings (core/lip_blink.h): the drawing per frame a Spine slot is keyed
// with must be the one ConvertMouth / ConvertEyes paint as levels. Checked against the
// converters' own values on random speech, random eye curves and auto-blinks.
#include <gtest/gtest.h>

#include <vector>

#include "core/lip_blink.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

// The level a drawing stands for with closed 0, mid 0.5, open 1.
double Level(MouthShape shape) {
  return shape == MouthShape::kClosed ? 0.0 : shape == MouthShape::kMid ? 0.5 : 1.0;
}

TEST(LipBlinkDrawingsTest, MouthDrawingsAreConvertMouthsLevels) {
  SplitMix64 random(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int frames = 20 + static_cast<int>(random.Next() % 200);
    MouthOptions options;
    options.min = 0.0;
    options.max = 1.0;
    options.frames_per_shape = 1 + static_cast<int>(random.Next() % 4);
    options.mode = trial % 2 ? MouthMode::kFollow : MouthMode::kRandom;
    options.detect_speech = false;
    for (int f = static_cast<int>(random.Next() % 5); f + 2 < frames;) {
      const int end = std::min(frames, f + 1 + static_cast<int>(random.Next() % 30));
      options.speech.push_back({f, end});
      f = end + 1 + static_cast<int>(random.Next() % 10);
    }
    std::vector<double> input(static_cast<size_t>(frames));
    for (double& v : input) v = static_cast<double>(random.Next() % 3) / 2;
    // Outside speech the mouth keeps its input; the Spine path sends a closed mouth (0).
    std::vector<double> closed_outside = input;
    std::vector<bool> in_speech(static_cast<size_t>(frames), false);
    for (const FrameInterval& i : options.speech) {
      for (int f = i.begin; f < i.end; ++f) in_speech[f] = true;
    }
    for (int f = 0; f < frames; ++f) {
      if (!in_speech[f]) closed_outside[f] = 0.0;
    }
    const MouthResult mouth = ConvertMouth(closed_outside, options, 100 + trial);
    const std::vector<MouthShape> drawings = MouthDrawings(mouth.holds, frames);
    ASSERT_EQ(drawings.size(), mouth.values.size());
    for (int f = 0; f < frames; ++f) {
      ASSERT_EQ(Level(drawings[f]), mouth.values[f]) << "trial " << trial << " frame " << f;
    }
  }
}

TEST(LipBlinkDrawingsTest, BlinkDrawingsAreConvertEyesLevels) {
  SplitMix64 random(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int frames = 30 + static_cast<int>(random.Next() % 400);
    // An open eye with closed runs (the Spine eye slot's closed keys) and a few half frames.
    std::vector<double> eye(static_cast<size_t>(frames), 1.0);
    for (int f = 0; f < frames; ++f) {
      const uint64_t r = random.Next() % 40;
      if (r == 0) {
        const int run = 1 + static_cast<int>(random.Next() % 6);
        for (int g = f; g < std::min(frames, f + run); ++g) eye[g] = 0.0;
        f += run;
      }
    }
    EyeOptions options;
    options.min = 0.0;
    options.max = 1.0;
    options.fps = 24.0;
    options.auto_blink.enabled = trial % 2 == 0;
    options.auto_blink.mean_interval_s = 1.0 + static_cast<double>(random.Next() % 3);
    options.auto_blink.spread_s = 0.5;  // must stay below the mean (ValidateEyeOptions)
    ASSERT_TRUE(ValidateEyeOptions(options, frames).ok());
    options.auto_blink.hold = 1 + static_cast<int>(random.Next() % 3);
    const EyeResult result = ConvertEyes({eye}, options, 500 + trial);
    const std::vector<MouthShape> drawings = BlinkDrawings(result.blinks[0], frames);
    // Outside blinks the eye keeps its input: open here, since every closed run is a blink.
    for (int f = 0; f < frames; ++f) {
      ASSERT_EQ(Level(drawings[f]), result.values[0][f]) << "trial " << trial << " frame " << f;
    }
  }
}

TEST(LipBlinkDrawingsTest, CutAtTheClipsEnd) {
  std::vector<MouthShape> mouth(10, MouthShape::kClosed);
  mouth[8] = mouth[9] = MouthShape::kOpen;
  EXPECT_EQ(MouthDrawings({{8, 5, MouthShape::kOpen}}, 10), mouth);
  Blink blink;
  blink.closing_begin = 3;
  blink.closed_begin = 4;
  blink.closed_end = 4;
  blink.open_span = 2;
  blink.hold = 2;
  const std::vector<MouthShape> d = BlinkDrawings({blink}, 7);
  EXPECT_EQ(d, (std::vector<MouthShape>{MouthShape::kOpen, MouthShape::kOpen, MouthShape::kOpen,
                                        MouthShape::kOpen, MouthShape::kClosed,
                                        MouthShape::kClosed, MouthShape::kMid}));
}

}  // namespace
}  // namespace koma

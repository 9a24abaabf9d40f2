// samples/pitch.bvh (made by samples/make_pitch_bvh.py) parses and has the slow / fast / slow speed
// profile the demos rely on.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "formats/bvh.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

constexpr int kThrowStart = 70;  // frames, from the generator's docstring
constexpr int kThrowEnd = 85;

bool IsRotation(ChannelKind kind) {
  return kind == ChannelKind::kXRotation || kind == ChannelKind::kYRotation ||
         kind == ChannelKind::kZRotation;
}

// speed[k] = sum over rotation channels of (value[k] - value[k-1])^2, in degrees^2 per frame^2;
// speed[0] = 0. Crude, but it needs no forward kinematics.
std::vector<double> RotationSpeed(const SkeletalClip& clip) {
  std::vector<int> rotation_columns;
  int column = 0;
  for (const Joint& joint : clip.skeleton.joints) {
    for (ChannelKind kind : joint.channels) {
      if (IsRotation(kind)) rotation_columns.push_back(column);
      ++column;
    }
  }
  std::vector<double> speed(clip.frame_count, 0.0);
  for (int k = 1; k < clip.frame_count; ++k) {
    for (int c : rotation_columns) {
      const double delta = clip.values[k * column + c] - clip.values[(k - 1) * column + c];
      speed[k] += delta * delta;
    }
  }
  return speed;
}

class PitchSampleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<SkeletalClip> clip = ParseBvh(ReadTestFile(KOMA_SAMPLES_DIR "/pitch.bvh"));
    ASSERT_TRUE(clip.ok()) << clip.status();
    clip_ = *std::move(clip);
  }
  SkeletalClip clip_;
};

TEST_F(PitchSampleTest, IsA130FrameHumanoidAt24Fps) {
  EXPECT_EQ(clip_.frame_count, 130);
  EXPECT_EQ(clip_.frame_time, 0.0416667);
  ASSERT_GE(clip_.skeleton.joints.size(), 20u);
  const Joint& hips = clip_.skeleton.joints[0];
  EXPECT_EQ(hips.name, "Hips");
  EXPECT_EQ(hips.parent, -1);
  EXPECT_EQ(hips.channels.size(), 6u);
  int end_sites = 0;
  for (const Joint& joint : clip_.skeleton.joints) {
    end_sites += static_cast<int>(joint.end_sites.size());
    if (joint.parent >= 0) {  // single root; rotation channels Z, X, Y
      EXPECT_THAT(joint.channels,
                  ::testing::ElementsAre(ChannelKind::kZRotation, ChannelKind::kXRotation,
                                         ChannelKind::kYRotation))
          << joint.name;
    }
  }
  EXPECT_EQ(end_sites, 5);  // head, hands, toes
}

TEST_F(PitchSampleTest, SpeedPeaksInTheThrowAndIsSmallAtBothEnds) {
  const std::vector<double> speed = RotationSpeed(clip_);
  const auto peak = std::max_element(speed.begin(), speed.end());
  const int peak_frame = static_cast<int>(peak - speed.begin());
  EXPECT_GE(peak_frame, kThrowStart);
  EXPECT_LE(peak_frame, kThrowEnd);
  // The wind-up and the follow-through stay well below the throw.
  const double wind_up = *std::max_element(speed.begin(), speed.begin() + kThrowStart - 2);
  const double follow = *std::max_element(speed.begin() + kThrowEnd + 5, speed.end());
  EXPECT_LT(wind_up, *peak / 5) << "wind-up peak " << wind_up << " vs " << *peak;
  EXPECT_LT(follow, *peak / 5) << "follow-through peak " << follow << " vs " << *peak;
  // Nearly still at the start and at the end.
  for (int k : {1, 2, 3, 127, 128, 129}) EXPECT_LT(speed[k], *peak / 200) << "frame " << k;
}

}  // namespace
}  // namespace koma::formats

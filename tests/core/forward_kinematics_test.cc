// Expected positions are worked out by hand below each clip, with the right-handed axis
// rotations (column vectors): Rz(90): x -> y, y -> -x; Rx(90): y -> z, z -> -y;
// Ry(90): z -> x, x -> -z.
#include "core/forward_kinematics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <vector>

#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

constexpr double kTolerance = 1e-9;  // cos(90 deg) is 6e-17, not 0

using C = ChannelKind;

void ExpectPosition(const std::vector<double>& positions, int joint_count, int frame, int joint,
                    Vec3 expected) {
  const size_t k = (static_cast<size_t>(frame) * joint_count + joint) * 3;
  ASSERT_LT(k + 2, positions.size());
  EXPECT_NEAR(positions[k], expected.x, kTolerance) << "frame " << frame << " joint " << joint;
  EXPECT_NEAR(positions[k + 1], expected.y, kTolerance) << "frame " << frame << " joint " << joint;
  EXPECT_NEAR(positions[k + 2], expected.z, kTolerance) << "frame " << frame << " joint " << joint;
}

// root (position + ZXY rotation) -> arm (XYZ rotation) -> hand (no channels).
SkeletalClip ChainClip() {
  SkeletalClip clip;
  clip.skeleton.joints = {
      {"root",
       -1,
       {1, 2, 3},
       {C::kXPosition, C::kYPosition, C::kZPosition, C::kZRotation, C::kXRotation, C::kYRotation},
       {}},
      {"arm", 0, {0, 2, 0}, {C::kXRotation, C::kYRotation, C::kZRotation}, {}},
      {"hand", 1, {0, 0, 3}, {}, {Vec3{0, 0, 1}}},
  };
  clip.frame_time = 1.0 / 30.0;
  clip.frame_count = 2;
  clip.values = {10, 20, 30, 90, 90, 0, 90, 90, 0,   // frame 0
                 0,  0,  0,  0,  0,  0, 0,  0,  0};  // frame 1: rest pose
  return clip;
}

TEST(ForwardKinematicsTest, ChainWithRotationsInListedOrder) {
  ASSERT_OK_AND_ASSIGN(const std::vector<double> p, ComputeWorldPositions(ChainClip()));
  ASSERT_EQ(p.size(), 2u * 3u * 3u);  // end sites are not joints
  // root = offset + position channels = (1, 2, 3) + (10, 20, 30).
  ExpectPosition(p, 3, 0, 0, {11, 22, 33});
  // R0 = Rz(90) Rx(90): (0, 2, 0) -Rx-> (0, 0, 2) -Rz-> (0, 0, 2). (Rx Rz would give
  // (-2, 0, 0), so this also pins the order.)
  ExpectPosition(p, 3, 0, 1, {11, 22, 35});
  // R1 = Rx(90) Ry(90): (0, 0, 3) -Ry-> (3, 0, 0) -Rx-> (3, 0, 0); then R0:
  // (3, 0, 0) -Rx-> (3, 0, 0) -Rz-> (0, 3, 0). (Ry Rx would give (0, -3, 0) before R0.)
  ExpectPosition(p, 3, 0, 2, {11, 25, 35});
}

TEST(ForwardKinematicsTest, RestPoseIsTheSumOfOffsets) {
  ASSERT_OK_AND_ASSIGN(const std::vector<double> p, ComputeWorldPositions(ChainClip()));
  ExpectPosition(p, 3, 1, 0, {1, 2, 3});
  ExpectPosition(p, 3, 1, 1, {1, 4, 3});
  ExpectPosition(p, 3, 1, 2, {1, 4, 6});
}

TEST(ForwardKinematicsTest, ChildWithSixChannelsInMixedOrder) {
  SkeletalClip clip;
  clip.skeleton.joints = {
      {"root", -1, {0, 0, 0}, {C::kYRotation}, {}},
      // Position channels add to the offset wherever they appear in the list.
      {"six",
       0,
       {1, 0, 0},
       {C::kZRotation, C::kXPosition, C::kYRotation, C::kYPosition, C::kXRotation, C::kZPosition},
       {}},
      {"tip", 1, {1, 0, 0}, {}, {}},
  };
  clip.frame_count = 1;
  clip.values = {90, /*six:*/ 90, 2, 0, 3, 0, 4};
  ASSERT_OK_AND_ASSIGN(const std::vector<double> p, ComputeWorldPositions(clip));
  ExpectPosition(p, 3, 0, 0, {0, 0, 0});
  // six = Ry(90) * ((1, 0, 0) + (2, 3, 4)) = Ry(90) * (3, 3, 4) = (4, 3, -3).
  ExpectPosition(p, 3, 0, 1, {4, 3, -3});
  // tip = six + Ry(90) Rz(90) (1, 0, 0) = six + Ry(90) (0, 1, 0) = (4, 4, -3).
  ExpectPosition(p, 3, 0, 2, {4, 4, -3});
}

TEST(ForwardKinematicsTest, SmallAngleMatchesTrigonometry) {
  SkeletalClip clip;
  clip.skeleton.joints = {{"root", -1, {0, 0, 0}, {C::kZRotation}, {}},
                          {"bone", 0, {2, 0, 0}, {}, {}}};
  clip.frame_count = 1;
  clip.values = {30};
  ASSERT_OK_AND_ASSIGN(const std::vector<double> p, ComputeWorldPositions(clip));
  // 30 degrees about z: (2 cos 30, 2 sin 30, 0) = (sqrt(3), 1, 0).
  ExpectPosition(p, 2, 0, 1, {1.7320508075688772, 1, 0});
}

TEST(ForwardKinematicsTest, ValueCountMustMatchFramesTimesChannels) {
  SkeletalClip clip = ChainClip();
  clip.values.pop_back();
  EXPECT_THAT(ComputeWorldPositions(clip),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("values: expected 18 values (2 frames x 9 channels), got 17")));
}

TEST(ForwardKinematicsTest, InvalidSkeletonIsReported) {
  SkeletalClip clip = ChainClip();
  clip.skeleton.joints[2].parent = 2;
  EXPECT_THAT(ComputeWorldPositions(clip),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("joints[2].parent")));
}

TEST(ForwardKinematicsTest, ZeroFramesGiveNoPositions) {
  SkeletalClip clip = ChainClip();
  clip.frame_count = 0;
  clip.values.clear();
  ASSERT_OK_AND_ASSIGN(const std::vector<double> p, ComputeWorldPositions(clip));
  EXPECT_TRUE(p.empty());
}

}  // namespace
}  // namespace koma

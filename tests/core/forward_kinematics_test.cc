// Expected positions are worked out by hand below each clip, with the right-handed axis
// rotations (column vectors): Rz(90): x -> y, y -> -x; Rx(90): y -> z, z -> -y;
// Ry(90): z -> x, x -> -z.
#include "core/forward_kinematics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/split_mix64.h"
#include "core/trig_degrees.h"
#include "tests/testing/long_chain_clip.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

constexpr double kTolerance = 1e-9;  // cos(90 deg) is 6e-17, not 0

using C = ChannelKind;

void ExpectPosition(const LargeArray<double>& positions, int joint_count, int frame, int joint,
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
  ASSERT_OK_AND_ASSIGN(const LargeArray<double> p, ComputeWorldPositions(ChainClip()));
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
  ASSERT_OK_AND_ASSIGN(const LargeArray<double> p, ComputeWorldPositions(ChainClip()));
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
  ASSERT_OK_AND_ASSIGN(const LargeArray<double> p, ComputeWorldPositions(clip));
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
  ASSERT_OK_AND_ASSIGN(const LargeArray<double> p, ComputeWorldPositions(clip));
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
  ASSERT_OK_AND_ASSIGN(const LargeArray<double> p, ComputeWorldPositions(clip));
  EXPECT_TRUE(p.empty());
}

// The reference: one frame at a time, written as plainly as possible. Same operations in the
// same order as the four-frames-per-lane ComputeWorldPositions, so that must match it bit for
// bit.
std::vector<double> ReferencePositions(const Skeleton& skeleton, const std::vector<double>& values,
                                       int frame_count) {
  struct Transform {
    double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double translation[3] = {0, 0, 0};
  };
  const std::vector<Joint>& joints = skeleton.joints;
  const size_t channel_count = static_cast<size_t>(ChannelCount(skeleton));
  std::vector<bool> has_children(joints.size(), false);
  for (const Joint& joint : joints) {
    if (joint.parent >= 0) has_children[joint.parent] = true;
  }
  std::vector<double> positions;
  std::vector<Transform> world(joints.size());
  for (int f = 0; f < frame_count; ++f) {
    const double* frame = values.data() + f * channel_count;
    size_t first_channel = 0;
    for (size_t j = 0; j < joints.size(); ++j) {
      const Joint& joint = joints[j];
      const double* channel = frame + first_channel;
      first_channel += joint.channels.size();
      double local[3] = {joint.offset.x, joint.offset.y, joint.offset.z};
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const ChannelKind kind = joint.channels[c];
        if (kind == C::kXPosition || kind == C::kYPosition || kind == C::kZPosition) {
          local[static_cast<int>(kind)] += channel[c];
        }
      }
      // world = parent * T(local) * R(c1) * R(c2) * ...: the rotation starts as the parent's
      // (identity at the root) and each rotation channel multiplies it on the right.
      Transform& out = world[j];
      const Transform identity;
      const Transform& parent = joint.parent < 0 ? identity : world[joint.parent];
      for (int r = 0; r < 3; ++r) {
        out.translation[r] = joint.parent < 0
                                 ? local[r]
                                 : parent.translation[r] + parent.rotation[3 * r] * local[0] +
                                       parent.rotation[3 * r + 1] * local[1] +
                                       parent.rotation[3 * r + 2] * local[2];
      }
      if (!has_children[j]) {
        for (double t : out.translation) positions.push_back(t);
        continue;
      }
      std::copy(std::begin(parent.rotation), std::end(parent.rotation), out.rotation);
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const ChannelKind kind = joint.channels[c];
        if (kind == C::kXPosition || kind == C::kYPosition || kind == C::kZPosition) continue;
        const SinCos sc = SinCosDegrees(channel[c]);
        const int i = kind == C::kXRotation ? 1 : kind == C::kYRotation ? 2 : 0;
        const int k = kind == C::kXRotation ? 2 : kind == C::kYRotation ? 0 : 1;
        for (int r = 0; r < 3; ++r) {
          const double a = out.rotation[3 * r + i];
          const double b = out.rotation[3 * r + k];
          out.rotation[3 * r + i] = sc.cos * a + sc.sin * b;
          out.rotation[3 * r + k] = sc.cos * b - sc.sin * a;
        }
      }
      for (double t : world[j].translation) positions.push_back(t);
    }
  }
  return positions;
}

// Random skeletons (trees of 1-40 joints, 0-6 channels per joint in any order, position
// channels anywhere), 0-13 frames (every remainder of the four-frame groups) and some longer
// clips, angles from tiny to many turns: bit-identical to the reference.
TEST(ForwardKinematicsTest, FourFramesAtOnceEqualOneFrameAtATimeBitForBit) {
  SplitMix64 rng(31);
  const C kinds[] = {C::kXPosition, C::kYPosition, C::kZPosition,
                     C::kXRotation, C::kYRotation, C::kZRotation};
  for (int clip = 0; clip < 400; ++clip) {
    Skeleton skeleton;
    const int joint_count = rng.Int(1, 40);
    for (int j = 0; j < joint_count; ++j) {
      Joint joint;
      joint.name = "j" + std::to_string(j);
      joint.parent = j == 0 ? -1 : rng.Int(0, j - 1);
      joint.offset = {rng.Unit() * 20 - 10, rng.Unit() * 20 - 10, rng.Unit() * 20 - 10};
      // A random subset of the six channels in a random order (a kind may appear once).
      std::vector<C> order(std::begin(kinds), std::end(kinds));
      for (int c = 5; c > 0; --c) std::swap(order[c], order[rng.Int(0, c)]);
      order.resize(rng.Int(0, 6));
      joint.channels.assign(order.begin(), order.end());
      skeleton.joints.push_back(joint);
    }
    const int frames = clip % 14 + (clip % 9 == 0 ? rng.Int(0, 200) : 0);
    std::vector<double> values(static_cast<size_t>(frames) * ChannelCount(skeleton));
    for (double& v : values) {
      v = rng.OneIn(6) ? 90.0 * rng.Int(-8, 8) : (rng.Unit() - 0.5) * (rng.OneIn(3) ? 1e-6 : 2000);
    }
    ASSERT_OK_AND_ASSIGN(const LargeArray<double> fast,
                         ComputeWorldPositions(skeleton, values, frames));
    const std::vector<double> want = ReferencePositions(skeleton, values, frames);
    ASSERT_EQ(fast.size(), want.size()) << "clip " << clip;
    for (size_t k = 0; k < want.size(); ++k) {
      ASSERT_EQ(std::memcmp(&fast[k], &want[k], sizeof(double)), 0)
          << "clip " << clip << " value " << k << ": " << fast[k] << " vs " << want[k];
    }
  }
}

// A runner that offers `parallelism` threads but runs the pieces on the calling thread, last
// first: the pieces must not depend on each other's order. Counts the pieces it was given.
class ReversedTaskRunner final : public TaskRunner {
 public:
  explicit ReversedTaskRunner(int parallelism) : parallelism_(parallelism) {}
  int Parallelism() const override { return parallelism_; }
  void Run(int count, absl::FunctionRef<void(int)> task) const override {
    pieces_ += count;
    for (int i = count - 1; i >= 0; --i) task(i);
  }
  int pieces() const { return pieces_; }

 private:
  int parallelism_;
  mutable int pieces_ = 0;
};

// Long clips split into stretches (whole four-frame groups, the last one shorter), one per
// thread the runner offers: the same bits as one stretch, whatever the count and order.
// (tests/platform/thread_task_runner_test runs them on real threads.)
TEST(ForwardKinematicsTest, ThreadsShareTheFramesWithTheSameBits) {
  SplitMix64 rng(41);
  const Skeleton skeleton = testing::FiveJointChain();
  for (const int frames : {kFramesPerFkThread * 2 - 1, kFramesPerFkThread * 3 + 5}) {
    const std::vector<double> values = testing::RandomChannelValues(skeleton, frames, rng);
    ASSERT_OK_AND_ASSIGN(const LargeArray<double> one,
                         ComputeWorldPositions(skeleton, values, frames));
    for (const int threads : {2, 3, 7}) {
      const ReversedTaskRunner runner(threads);
      ASSERT_OK_AND_ASSIGN(const LargeArray<double> many,
                           ComputeWorldPositions(skeleton, values, frames, runner));
      // Each stretch at least kFramesPerFkThread frames: 2 for the shorter clip, 3 at most.
      EXPECT_EQ(runner.pieces(), std::min(threads, frames / kFramesPerFkThread));
      ASSERT_EQ(many.size(), one.size());
      EXPECT_EQ(std::memcmp(many.data(), one.data(), sizeof(double) * one.size()), 0)
          << frames << " frames, " << threads << " threads";
    }
    // Extra capacity (room the server keeps for the response) changes nothing but capacity.
    const size_t room = one.size() * 2 + 17;
    ASSERT_OK_AND_ASSIGN(const LargeArray<double> roomy,
                         ComputeWorldPositions(skeleton, values, frames,
                                               ReversedTaskRunner(2), room));
    ASSERT_EQ(roomy.size(), one.size());
    EXPECT_GE(roomy.capacity(), room);
    EXPECT_EQ(std::memcmp(roomy.data(), one.data(), sizeof(double) * one.size()), 0);
  }
}

}  // namespace
}  // namespace koma

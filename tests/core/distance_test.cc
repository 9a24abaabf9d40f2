#include "core/distance.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>
#include <vector>

#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 3 frames x 2 joints. Joint 0 (root) walks along x; joint 1 rides 1 above it and swings.
const std::vector<double> kPositions = {
    0, 0, 0, /**/ 0, 1, 0,  // frame 0
    1, 0, 0, /**/ 1, 1, 2,  // frame 1
    3, 0, 0, /**/ 3, 1, 2,  // frame 2
};

// clip.x = 2x + 1, clip.y = 3y, clip.w = z; column-major: columns are (2,0,0,0), (0,3,0,0),
// (0,0,1,1) and the translation (1,0,0,0).
constexpr std::array<double, 16> kCamera = {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0};

TEST(DistanceTest, DefaultWeightsSumSquaredDistances) {
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(kPositions, 3, 2, {}));
  EXPECT_EQ(d.frame_count(), 3);
  EXPECT_EQ(d.joint_count(), 2);
  EXPECT_EQ(d(0, 1), 1.0 + (1.0 + 4.0));  // root moves 1; joint 1 moves (1, 0, 2)
  EXPECT_EQ(d(1, 2), 4.0 + 4.0);
  EXPECT_EQ(d(0, 2), 9.0 + (9.0 + 4.0));
  EXPECT_EQ(d(2, 0), d(0, 2));
  EXPECT_EQ(d(1, 1), 0.0);
}

TEST(DistanceTest, WeightsScaleEachJoint) {
  DistanceOptions options;
  options.weights = {0.5, 2.0};
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(kPositions, 3, 2, options));
  EXPECT_EQ(d(0, 1), 0.5 * 1.0 + 2.0 * 5.0);
}

TEST(DistanceTest, RootRelativeIgnoresLocomotion) {
  DistanceOptions options;
  options.root_relative = true;
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(kPositions, 3, 2, options));
  EXPECT_EQ(d(0, 1), 4.0);  // joint 1 relative to the root: (0, 1, 0) -> (0, 1, 2)
  EXPECT_EQ(d(1, 2), 0.0);  // pure translation
}

TEST(DistanceTest, InputSsdStartsWithZero) {
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(kPositions, 3, 2, {}));
  EXPECT_THAT(d.InputSsd(), ElementsAre(0.0, 6.0, 8.0));
}

TEST(DistanceTest, CameraProjectsColumnMajorToNdc) {
  // One joint at (1, 1, 2) then (1, 1, 4): ndc (3/2, 3/2) then (3/4, 3/4).
  const std::vector<double> positions = {1, 1, 2, 1, 1, 4};
  DistanceOptions options;
  options.camera = kCamera;
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(positions, 2, 1, options));
  EXPECT_EQ(d(0, 1), 0.75 * 0.75 + 0.75 * 0.75);
}

TEST(DistanceTest, CameraUsesOnlyScreenComponents) {
  // With x = -0.5 and y = 0, clip x = 2x + 1 = 0 and clip y = 0: moving along z (depth)
  // does not move the point on screen, so the distance is 0 though it moved 6 in world.
  const std::vector<double> positions = {-0.5, 0, 2, -0.5, 0, 8};
  DistanceOptions options;
  options.camera = kCamera;
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(positions, 2, 1, options));
  EXPECT_EQ(d(0, 1), 0.0);
}

TEST(DistanceTest, RootRelativeIsAppliedInWorldSpaceBeforeTheCamera) {
  // w = z + 1, clip.x = x. Joint 1 relative to the root: (1, 0, 1) then (1, 0, 3), so ndc x
  // 1/2 then 1/4; the root itself sits at the origin, ndc (0, 0).
  std::array<double, 16> camera = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1};
  const std::vector<double> positions = {5, 0, 10, 6, 0, 11, /**/ 7, 0, 20, 8, 0, 23};
  DistanceOptions options;
  options.root_relative = true;
  options.camera = camera;
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(positions, 2, 2, options));
  EXPECT_EQ(d(0, 1), 0.25 * 0.25);
}

TEST(DistanceTest, CameraWZeroIsRejectedWithFrameAndJoint) {
  const std::vector<double> positions = {1, 1, 2, 1, 1, 2, /**/ 1, 1, 2, 1, 1, 0};
  DistanceOptions options;
  options.camera = kCamera;
  EXPECT_THAT(FrameDistance::Create(positions, 2, 2, options),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("camera: frame 1 joint 1 projects with w = 0")));
}

TEST(DistanceTest, ZeroWeightJointsTakeNoPart) {
  // Joint 1 is behind the camera plane (w = 0) and huge, but has weight 0.
  const std::vector<double> positions = {1, 1, 2, 1e300, 1, 0, /**/ 1, 1, 4, -1e300, 1, 0};
  DistanceOptions options;
  options.camera = kCamera;
  options.weights = {1.0, 0.0};
  ASSERT_OK_AND_ASSIGN(const FrameDistance d, FrameDistance::Create(positions, 2, 2, options));
  EXPECT_EQ(d(0, 1), 0.75 * 0.75 + 0.75 * 0.75);
  options.camera.reset();
  ASSERT_OK_AND_ASSIGN(const FrameDistance world, FrameDistance::Create(positions, 2, 2, options));
  EXPECT_EQ(world(0, 1), 4.0);  // not NaN from 0 * inf
}

TEST(DistanceTest, NegativeWeightIsRejected) {
  DistanceOptions options;
  options.weights = {1.0, -1.0};
  EXPECT_THAT(
      FrameDistance::Create(kPositions, 3, 2, options),
      StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("weights[1]: -1 is negative")));
}

TEST(DistanceTest, NonFiniteWeightIsRejected) {
  DistanceOptions options;
  options.weights = {kNaN, 1.0};
  EXPECT_THAT(
      FrameDistance::Create(kPositions, 3, 2, options),
      StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("weights[0]: nan is not finite")));
}

TEST(DistanceTest, WeightCountMustMatchJoints) {
  DistanceOptions options;
  options.weights = {1.0, 1.0, 1.0};
  EXPECT_THAT(
      FrameDistance::Create(kPositions, 3, 2, options),
      StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("weights: 3 weights for 2 joints")));
  options.weights = {0.0, 0.0};
  EXPECT_THAT(FrameDistance::Create(kPositions, 3, 2, options), IsOk());
}

TEST(DistanceTest, SizesMustAgree) {
  EXPECT_THAT(
      FrameDistance::Create(kPositions, 4, 2, {}),
      StatusIs(absl::StatusCode::kInvalidArgument,
               HasSubstr("world_positions: expected 24 values (4 frames x 2 joints x 3), got 18")));
  EXPECT_THAT(FrameDistance::Create({}, 0, 2, {}),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("frame_count: 0")));
  EXPECT_THAT(FrameDistance::Create({}, 1, 0, {}),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("joint_count: 0")));
}

TEST(DistanceTest, NonFinitePositionIsRejectedWithItsPlace) {
  std::vector<double> positions = kPositions;
  positions[16] = kNaN;  // frame 2, joint 1, y
  EXPECT_THAT(FrameDistance::Create(positions, 3, 2, {}),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("world_positions[16]: nan is not finite (frame 2 joint 1 y)")));
}

TEST(DistanceTest, NonFiniteCameraEntryIsRejected) {
  DistanceOptions options;
  options.camera = kCamera;
  (*options.camera)[7] = kNaN;
  EXPECT_THAT(
      FrameDistance::Create(kPositions, 3, 2, options),
      StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("camera[7]: nan is not finite")));
}

// CreateView reads the positions in place when no transform applies, and copies (as Create)
// when one does; either way every distance is bit-identical to Create's.
TEST(DistanceTest, CreateViewGivesTheSameDistancesAsCreate) {
  DistanceOptions root_relative;
  root_relative.root_relative = true;
  DistanceOptions zero_weight;
  zero_weight.weights = {1.0, 0.0};
  DistanceOptions camera;
  camera.camera = std::array<double, 16>{2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1};  // w = 1
  for (const DistanceOptions& options : {DistanceOptions{}, root_relative, zero_weight, camera}) {
    ASSERT_OK_AND_ASSIGN(const FrameDistance copied,
                         FrameDistance::Create(kPositions, 3, 2, options));
    ASSERT_OK_AND_ASSIGN(const FrameDistance viewed,
                         FrameDistance::CreateView(kPositions, 3, 2, options));
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) EXPECT_EQ(viewed(a, b), copied(a, b)) << a << " " << b;
    }
  }
}

TEST(DistanceTest, CreateViewStillRefusesOverflowingPositions) {
  std::vector<double> positions = kPositions;
  positions[3] = 1e200;
  EXPECT_THAT(FrameDistance::CreateView(positions, 3, 2, {}),
              StatusIs(absl::StatusCode::kOutOfRange, HasSubstr("largest |coordinate| 1e+200")));
}

// Finite positions whose squared differences would overflow are refused up front, so no
// distance is ever inf (or NaN from inf - inf) inside the retiming orderings.
TEST(DistanceTest, PositionsThatWouldOverflowTheDistanceAreOutOfRange) {
  std::vector<double> positions = kPositions;
  positions[3] = 1e200;  // frame 0, joint 1, x
  EXPECT_THAT(FrameDistance::Create(positions, 3, 2, {}),
              StatusIs(absl::StatusCode::kOutOfRange,
                       HasSubstr("largest |coordinate| 1e+200 with total weight 2")));
  positions[3] = 1e150;  // (2e150)^2 * 3 * 2 is still far below DBL_MAX
  EXPECT_THAT(FrameDistance::Create(positions, 3, 2, {}), IsOk());
}

// Root-relative subtraction of two huge coordinates overflows to inf: refused too.
TEST(DistanceTest, RootRelativeOverflowIsOutOfRange) {
  std::vector<double> positions = kPositions;
  positions[0] = -1.5e308;  // root x in frame 0
  positions[3] = 1.5e308;   // joint 1 x in frame 0
  DistanceOptions options;
  options.root_relative = true;
  EXPECT_THAT(FrameDistance::Create(positions, 3, 2, options),
              StatusIs(absl::StatusCode::kOutOfRange, HasSubstr("largest |coordinate| inf")));
}

// The tables of AdjacentDistances (an unrolled, partly SIMD loop) must equal operator() bit for
// bit: RetimeFast mixes both, and the tie rules compare them exactly. Random clips of every
// small length (the loop's tail), 1-40 joints, random weights with zeros, mixed scales.
TEST(DistanceTest, AdjacentDistancesEqualOperatorBitForBit) {
  SplitMix64 rng(77);
  for (int clip = 0; clip < 300; ++clip) {
    const int frames = 1 + clip % 40 + (clip % 7 == 0 ? rng.Int(0, 500) : 0);
    const int joints = rng.Int(1, 40);
    std::vector<double> positions(static_cast<size_t>(frames) * joints * 3);
    const double scale = rng.OneIn(2) ? 1e-3 : 1e3;
    for (double& p : positions) p = rng.OneIn(5) ? rng.Int(-2, 2) : scale * (rng.Unit() - 0.5);
    DistanceOptions options;
    if (!rng.OneIn(3)) {
      for (int j = 0; j < joints; ++j) options.weights.push_back(rng.OneIn(4) ? 0.0 : rng.Unit());
    }
    options.root_relative = rng.OneIn(4);
    ASSERT_OK_AND_ASSIGN(const FrameDistance d,
                         FrameDistance::Create(positions, frames, joints, options));
    std::vector<double> ssd, skip, skip2;
    d.AdjacentDistances(&ssd, &skip, &skip2);
    ASSERT_EQ(ssd.size(), static_cast<size_t>(frames));
    ASSERT_EQ(skip.size(), static_cast<size_t>(frames));
    ASSERT_EQ(skip2.size(), static_cast<size_t>(frames));
    auto bits_equal = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    for (int k = 0; k < frames; ++k) {
      const double want_ssd = k >= 1 ? d(k - 1, k) : 0.0;
      const double want_skip = k >= 1 && k + 1 < frames ? d(k - 1, k + 1) : 0.0;
      const double want_skip2 = k >= 1 && k + 2 < frames ? d(k - 1, k + 2) : 0.0;
      ASSERT_TRUE(bits_equal(ssd[k], want_ssd)) << "clip " << clip << " ssd[" << k << "]";
      ASSERT_TRUE(bits_equal(skip[k], want_skip)) << "clip " << clip << " skip[" << k << "]";
      ASSERT_TRUE(bits_equal(skip2[k], want_skip2)) << "clip " << clip << " skip2[" << k << "]";
    }
    // The four-lane pass for small clips, against the plain one (the same as operator()).
    const std::vector<double> plain = d.InputSsd();
    const std::vector<double> lanes = d.InputSsdOfSmallClip();
    ASSERT_EQ(lanes.size(), plain.size());
    for (int k = 0; k < frames; ++k) {
      ASSERT_TRUE(bits_equal(lanes[k], plain[k])) << "clip " << clip << " lanes[" << k << "]";
    }
  }
}

}  // namespace
}  // namespace koma

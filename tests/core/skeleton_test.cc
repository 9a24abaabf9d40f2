#include "core/skeleton.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// hips (6 channels) -> spine (3) -> head (3, one end site).
Skeleton ThreeJointSkeleton() {
  Skeleton skeleton;
  skeleton.joints.push_back(
      {"hips",
       -1,
       {0, 90, 0},
       {ChannelKind::kXPosition, ChannelKind::kYPosition, ChannelKind::kZPosition,
        ChannelKind::kZRotation, ChannelKind::kXRotation, ChannelKind::kYRotation},
       {}});
  skeleton.joints.push_back(
      {"spine",
       0,
       {0, 10, 0},
       {ChannelKind::kZRotation, ChannelKind::kXRotation, ChannelKind::kYRotation},
       {}});
  skeleton.joints.push_back(
      {"head",
       1,
       {0, 20, 0},
       {ChannelKind::kZRotation, ChannelKind::kXRotation, ChannelKind::kYRotation},
       {Vec3{0, 5, 0}}});
  return skeleton;
}

TEST(SkeletonTest, ChannelNamesRoundTrip) {
  for (ChannelKind kind :
       {ChannelKind::kXPosition, ChannelKind::kYPosition, ChannelKind::kZPosition,
        ChannelKind::kXRotation, ChannelKind::kYRotation, ChannelKind::kZRotation}) {
    ASSERT_OK_AND_ASSIGN(const ChannelKind parsed, ParseChannelName(ChannelName(kind)));
    EXPECT_EQ(parsed, kind) << ChannelName(kind);
  }
  EXPECT_EQ(ChannelName(ChannelKind::kYRotation), "Yrotation");
}

TEST(SkeletonTest, ParseChannelNameIsCaseSensitiveAndNamesTheInput) {
  EXPECT_THAT(ParseChannelName("xrotation"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("\"xrotation\"")));
  EXPECT_THAT(ParseChannelName(""),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("\"\"")));
  EXPECT_THAT(ParseChannelName("Wrotation"),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("expected Xposition")));
}

TEST(SkeletonTest, ChannelCountSumsAllJoints) {
  EXPECT_EQ(ChannelCount(ThreeJointSkeleton()), 12);
  EXPECT_EQ(ChannelCount(Skeleton{}), 0);
}

TEST(SkeletonTest, ValidSkeletonPasses) {
  EXPECT_THAT(ValidateSkeleton(ThreeJointSkeleton()), IsOk());
}

TEST(SkeletonTest, SeveralRootsAndChannellessJointsAreValid) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].parent = -1;  // a second root
  skeleton.joints[2].channels.clear();
  EXPECT_THAT(ValidateSkeleton(skeleton), IsOk());
}

TEST(SkeletonTest, Rule1NoJoints) {
  EXPECT_THAT(ValidateSkeleton(Skeleton{}),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("joints: ")));
}

TEST(SkeletonTest, Rule2ParentOutOfRange) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[2].parent = 3;
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[2].parent: 3 is out of range")));
  skeleton.joints[2].parent = -2;
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[2].parent: -2 is out of range")));
}

TEST(SkeletonTest, Rule2SelfParentIsACycle) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].parent = 1;
  EXPECT_THAT(ValidateSkeleton(skeleton), StatusIs(absl::StatusCode::kInvalidArgument,
                                                   HasSubstr("joints[1].parent: 1 forms a cycle")));
}

TEST(SkeletonTest, Rule2LoopThroughALaterJointIsACycle) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].parent = 2;  // 1 -> 2 -> 1
  EXPECT_THAT(ValidateSkeleton(skeleton), StatusIs(absl::StatusCode::kInvalidArgument,
                                                   HasSubstr("joints[1].parent: 2 forms a cycle")));
}

TEST(SkeletonTest, Rule2LaterParentWithoutLoopIsOutOfOrder) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].parent = 2;
  skeleton.joints[2].parent = 0;
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[1].parent: 2 must name an earlier joint")));
}

TEST(SkeletonTest, Rule3OffsetMustBeFinite) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].offset.y = std::numeric_limits<double>::infinity();
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[1].offset: (0, inf, 0) is not finite")));
}

TEST(SkeletonTest, Rule3EndSiteMustBeFinite) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[2].end_sites.push_back(Vec3{kNaN, 0, 0});
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[2].end_sites[1]: (nan, 0, 0) is not finite")));
}

TEST(SkeletonTest, Rule4AtMostSixChannels) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[0].channels.push_back(ChannelKind::kXRotation);
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[0].channels: 7 channels, at most 6 allowed")));
}

TEST(SkeletonTest, Rule4NoRepeatedChannel) {
  Skeleton skeleton = ThreeJointSkeleton();
  skeleton.joints[1].channels = {ChannelKind::kZRotation, ChannelKind::kZRotation};
  EXPECT_THAT(ValidateSkeleton(skeleton),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("joints[1].channels: Zrotation appears twice")));
}

}  // namespace
}  // namespace koma

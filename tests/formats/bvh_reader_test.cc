#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "formats/bvh.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

constexpr ChannelKind kXpos = ChannelKind::kXPosition;
constexpr ChannelKind kYpos = ChannelKind::kYPosition;
constexpr ChannelKind kZpos = ChannelKind::kZPosition;
constexpr ChannelKind kXrot = ChannelKind::kXRotation;
constexpr ChannelKind kYrot = ChannelKind::kYRotation;
constexpr ChannelKind kZrot = ChannelKind::kZRotation;

MATCHER_P3(Vec3Is, x, y, z, "") { return arg.x == x && arg.y == y && arg.z == z; }

TEST(ParseBvhTest, ReadsTabsCrlfAndShortFrameTime) {
  const std::string text = ReadTestFile(KOMA_TESTDATA_DIR "/two_joints_crlf.bvh");
  // Guard against the fixture being normalised by an editor or git.
  ASSERT_NE(text.find("\r\n"), std::string::npos);
  ASSERT_NE(text.find('\t'), std::string::npos);
  ASSERT_OK_AND_ASSIGN(const SkeletalClip clip, ParseBvh(text));

  ASSERT_EQ(clip.skeleton.joints.size(), 2u);
  const Joint& hips = clip.skeleton.joints[0];
  EXPECT_EQ(hips.name, "Hips");
  EXPECT_EQ(hips.parent, -1);
  EXPECT_THAT(hips.offset, Vec3Is(0.0, 0.0, 0.0));
  EXPECT_THAT(hips.channels, ElementsAre(kXpos, kYpos, kZpos, kZrot, kXrot, kYrot));
  EXPECT_THAT(hips.end_sites, IsEmpty());
  const Joint& chest = clip.skeleton.joints[1];
  EXPECT_EQ(chest.name, "Chest");
  EXPECT_EQ(chest.parent, 0);
  EXPECT_THAT(chest.offset, Vec3Is(0.0, 5.21, -0.5));
  EXPECT_THAT(chest.channels, ElementsAre(kZrot, kXrot, kYrot));
  EXPECT_THAT(chest.end_sites, ElementsAre(Vec3Is(0.0, 10.0, 0.0)));

  EXPECT_EQ(clip.frame_time,
            0.0083333);  // the double nearest to the text, exactly
  EXPECT_EQ(clip.frame_count, 3);
  EXPECT_THAT(clip.values, ElementsAre(1.5, 90, -2, 0, 0, 0, 10, 20, 30,              //
                                       1.5, 91.25, -2, 0.5, -0.5, 0.001, 11, 21, 31,  //
                                       1.5, 92.5, -2, 1, -1, 2, 12, 22, 32));
}

TEST(ParseBvhTest, ReadsUnusualChannelOrdersEndSitesRootsAndWrappedFrames) {
  const std::string text = ReadTestFile(KOMA_TESTDATA_DIR "/unusual_channels.bvh");
  ASSERT_OK_AND_ASSIGN(const SkeletalClip clip, ParseBvh(text));

  ASSERT_EQ(clip.skeleton.joints.size(), 4u);
  const Joint& body = clip.skeleton.joints[0];
  EXPECT_EQ(body.name, "Body");
  EXPECT_EQ(body.parent, -1);
  EXPECT_THAT(body.offset, Vec3Is(1.0, 2.0, 3.0));
  EXPECT_THAT(body.channels, ElementsAre(kYrot, kXpos, kZrot, kYpos, kXrot, kZpos));
  const Joint& wrist = clip.skeleton.joints[1];
  EXPECT_EQ(wrist.name, "Wrist");
  EXPECT_EQ(wrist.parent, 0);
  EXPECT_THAT(wrist.channels, IsEmpty());  // no CHANNELS line
  EXPECT_THAT(wrist.end_sites, ElementsAre(Vec3Is(0.0, -1.0, 0.0)));
  const Joint& hand = clip.skeleton.joints[2];
  EXPECT_EQ(hand.name, "Hand");
  EXPECT_EQ(hand.parent, 1);
  EXPECT_THAT(hand.offset, Vec3Is(0.0, -2.0, 0.25));
  EXPECT_THAT(hand.channels, ElementsAre(kYrot, kXrot, kZrot));
  EXPECT_THAT(hand.end_sites,
              ElementsAre(Vec3Is(-1.0, -1.0, 0.0), Vec3Is(0.0, -1.5, 0.0), Vec3Is(1.0, -1.0, 0.0)));
  const Joint& prop = clip.skeleton.joints[3];
  EXPECT_EQ(prop.name, "Prop");
  EXPECT_EQ(prop.parent, -1);  // a second root
  EXPECT_THAT(prop.channels, ElementsAre(kXpos, kYpos, kZpos));
  EXPECT_THAT(prop.end_sites, ElementsAre(Vec3Is(0.0, 0.0, 1.0)));

  EXPECT_EQ(clip.frame_time, 0.033333);
  EXPECT_EQ(clip.frame_count, 2);
  // Frame 0 spans three lines; frame 1 is one line.
  EXPECT_THAT(clip.values, ElementsAre(10, 0.5, 20, 1, 30, 1.5, 40, 50, 60, 7, 8, 9,  //
                                       11, 0.25, 21, 1.25, 31, 1.75, 41, 51, 61, -7, -8, -9));
}

TEST(ParseBvhTest, AcceptsZeroFramesAndJointsWithoutChannels) {
  ASSERT_OK_AND_ASSIGN(const SkeletalClip empty,
                       ParseBvh("HIERARCHY ROOT A { OFFSET 0 0 0 CHANNELS 1 Xrotation }\n"
                                "MOTION\nFrames: 0\nFrame Time: 0.5\n"));
  EXPECT_EQ(empty.frame_count, 0);
  EXPECT_THAT(empty.values, IsEmpty());

  ASSERT_OK_AND_ASSIGN(const SkeletalClip still,
                       ParseBvh("HIERARCHY ROOT A { OFFSET 0 0 0 CHANNELS 0 }\n"
                                "MOTION\nFrames: 2\nFrame Time: 0.5\n\n\n"));
  EXPECT_EQ(still.frame_count, 2);
  EXPECT_THAT(still.values, IsEmpty());
}

// No recursion in the reader: a 100000-joint chain is fine.
TEST(ParseBvhTest, ReadsADeepChainWithoutRecursion) {
  constexpr int kDepth = 100000;
  std::string text = "HIERARCHY\nROOT j0 { OFFSET 0 0 0 CHANNELS 1 Zrotation\n";
  for (int i = 1; i < kDepth; ++i) text += "JOINT j" + std::to_string(i) + " { OFFSET 0 1 0\n";
  for (int i = 0; i < kDepth; ++i) text += "}\n";
  text += "MOTION\nFrames: 1\nFrame Time: 1\n45\n";
  ASSERT_OK_AND_ASSIGN(const SkeletalClip clip, ParseBvh(text));
  ASSERT_EQ(clip.skeleton.joints.size(), static_cast<size_t>(kDepth));
  EXPECT_EQ(clip.skeleton.joints.back().parent, kDepth - 2);
  EXPECT_THAT(clip.values, ElementsAre(45));
}

// "Frames:" is not trusted for allocation: a huge count fails on the missing values.
TEST(ParseBvhTest, HugeFrameCountFailsWithoutAllocating) {
  EXPECT_THAT(ParseBvh("HIERARCHY ROOT A { OFFSET 0 0 0 CHANNELS 6 Xposition Yposition "
                       "Zposition Zrotation Xrotation Yrotation }\nMOTION\nFrames: "
                       "2147483647\n"
                       "Frame Time: 1\n1 2 3 4 5 6\n"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("line 5: expected 2147483647 frames of 6 values, got 1")));
}

TEST(ParseBvhTest, CountsLinesForEveryLineEnding) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    const std::string text = "HIERARCHY" + eol + "ROOT A" + eol + "{" + eol + eol + "OFFSET 0 0 0" +
                             eol + "CHANNELS 1 Xrot" + eol + "}" + eol;
    EXPECT_THAT(ParseBvh(text), StatusIs(absl::StatusCode::kInvalidArgument,
                                         HasSubstr("line 6: unknown channel name \"Xrot\"")));
  }
}

}  // namespace
}  // namespace koma::formats

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "formats/bvh.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::testing::ElementsAre;

void ExpectSameVec3(const Vec3& a, const Vec3& b, const std::string& where) {
  EXPECT_EQ(a.x, b.x) << where;
  EXPECT_EQ(a.y, b.y) << where;
  EXPECT_EQ(a.z, b.z) << where;
}

// Same structure and the same numbers (==, so -0 matches +0).
void ExpectSameClip(const SkeletalClip& a, const SkeletalClip& b) {
  ASSERT_EQ(a.skeleton.joints.size(), b.skeleton.joints.size());
  for (size_t j = 0; j < a.skeleton.joints.size(); ++j) {
    const Joint& ja = a.skeleton.joints[j];
    const Joint& jb = b.skeleton.joints[j];
    const std::string where = "joint " + std::to_string(j);
    EXPECT_EQ(ja.name, jb.name) << where;
    EXPECT_EQ(ja.parent, jb.parent) << where;
    ExpectSameVec3(ja.offset, jb.offset, where);
    EXPECT_EQ(ja.channels, jb.channels) << where;
    ASSERT_EQ(ja.end_sites.size(), jb.end_sites.size()) << where;
    for (size_t e = 0; e < ja.end_sites.size(); ++e) {
      ExpectSameVec3(ja.end_sites[e], jb.end_sites[e], where + " end site");
    }
  }
  EXPECT_EQ(a.frame_time, b.frame_time);
  EXPECT_EQ(a.frame_count, b.frame_count);
  EXPECT_EQ(a.values, b.values);
}

constexpr char kUnusualWritten[] =
    "HIERARCHY\nROOT Body\n{\n"
    "\tOFFSET 1 2 3\n"
    "\tCHANNELS 6 Yrotation Xposition Zrotation Yposition Xrotation Zposition\n"
    "\tJOINT Wrist\n\t{\n"
    "\t\tOFFSET 0 -4.5 0\n"
    "\t\tCHANNELS 0\n"
    "\t\tJOINT Hand\n\t\t{\n"
    "\t\t\tOFFSET 0 -2 0.25\n"
    "\t\t\tCHANNELS 3 Yrotation Xrotation Zrotation\n"
    "\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET -1 -1 0\n\t\t\t}\n"
    "\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET 0 -1.5 0\n\t\t\t}\n"
    "\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET 1 -1 0\n\t\t\t}\n"
    "\t\t}\n"
    "\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 -1 0\n\t\t}\n"  // after the child joint
    "\t}\n}\n"
    "ROOT Prop\n{\n"
    "\tOFFSET 10 0 0\n"
    "\tCHANNELS 3 Xposition Yposition Zposition\n"
    "\tEnd Site\n\t{\n\t\tOFFSET 0 0 1\n\t}\n"
    "}\n"
    "MOTION\nFrames: 2\nFrame Time: 0.033333\n"
    "10 0.5 20 1 30 1.5 40 50 60 7 8 9\n"
    "11 0.25 21 1.25 31 1.75 41 51 61 -7 -8 -9\n";

TEST(WriteBvhTest, WritesTheStandardLayout) {
  ASSERT_OK_AND_ASSIGN(const SkeletalClip clip,
                       ParseBvh(ReadTestFile(KOMA_TESTDATA_DIR "/unusual_channels.bvh")));
  EXPECT_EQ(WriteBvh(clip), kUnusualWritten);
}

TEST(WriteBvhTest, FixturesRoundTrip) {
  for (const char* name : {"/two_joints_crlf.bvh", "/unusual_channels.bvh"}) {
    SCOPED_TRACE(name);
    ASSERT_OK_AND_ASSIGN(const SkeletalClip read,
                         ParseBvh(ReadTestFile(std::string(KOMA_TESTDATA_DIR) + name)));
    const std::string written = WriteBvh(read);
    ASSERT_OK_AND_ASSIGN(const SkeletalClip reread, ParseBvh(written));
    ExpectSameClip(read, reread);
    EXPECT_EQ(WriteBvh(reread), written);
  }
}

// Joints 0 Root, 1 A (of Root), 2 B (of Root), 3 A1 (of A): depth-first order is Root, A, A1, B,
// and each frame's values follow that order.
TEST(WriteBvhTest, WritesJointsDepthFirstWithTheirValues) {
  SkeletalClip clip;
  clip.skeleton.joints = {{"Root", -1, {}, {ChannelKind::kXRotation}, {}},
                          {"A", 0, {0, 1, 0}, {ChannelKind::kYRotation}, {}},
                          {"B", 0, {0, 2, 0}, {ChannelKind::kZRotation}, {}},
                          {"A1", 1, {0, 3, 0}, {ChannelKind::kXPosition}, {}}};
  clip.frame_time = 0.5;
  clip.frame_count = 2;
  clip.values = {0, 1, 2, 3, 10, 11, 12, 13};
  const std::string written = WriteBvh(clip);
  EXPECT_THAT(written, ::testing::HasSubstr("MOTION\nFrames: 2\nFrame Time: 0.5\n"
                                            "0 1 3 2\n10 11 13 12\n"));
  ASSERT_OK_AND_ASSIGN(const SkeletalClip read, ParseBvh(written));
  std::vector<std::string> names;
  std::vector<int> parents;
  for (const Joint& joint : read.skeleton.joints) {
    names.push_back(joint.name);
    parents.push_back(joint.parent);
  }
  EXPECT_THAT(names, ElementsAre("Root", "A", "A1", "B"));
  EXPECT_THAT(parents, ElementsAre(-1, 0, 1, 0));
  EXPECT_THAT(read.values, ElementsAre(0, 1, 3, 2, 10, 11, 13, 12));
  EXPECT_EQ(WriteBvh(read), written);
}

TEST(WriteBvhTest, AwkwardNumbersReadBackExactly) {
  const std::vector<double> kValues = {0.1,    1.0 / 3.0, 1e-300,        1e300,
                                       5e-324, -1e-7,     123456789.123, -0.0};
  SkeletalClip clip;
  clip.skeleton.joints = {{"J", -1, {1.0 / 7.0, -2e-9, 3e20}, {}, {{0.1 + 0.2, 0, -0.0}}}};
  for (size_t i = 0; i < kValues.size(); ++i) {
    clip.skeleton.joints.push_back({"c" + std::to_string(i), 0, {}, {ChannelKind::kZRotation}, {}});
  }
  clip.frame_time = 1.0 / 120.0;
  clip.frame_count = 1;
  clip.values = kValues;
  const std::string written = WriteBvh(clip);
  EXPECT_THAT(written, ::testing::HasSubstr("Frame Time: 0.008333333333333333\n"));
  ASSERT_OK_AND_ASSIGN(const SkeletalClip read, ParseBvh(written));
  ExpectSameClip(clip, read);
  EXPECT_FALSE(std::signbit(read.values.back()));  // -0 is written as "0"
}

// A random skeleton in depth-first order: each joint's parent is on the path from a root to the
// previous joint, or it starts a new root.
SkeletalClip RandomClip(std::mt19937_64& rng) {
  SkeletalClip clip;
  const int joints = 1 + static_cast<int>(rng() % 12);
  std::vector<int> path;  // previous joint and its ancestors
  for (int j = 0; j < joints; ++j) {
    const int keep = j == 0 ? 0 : static_cast<int>(rng() % (path.size() + 1));
    path.resize(keep);
    Joint joint{"j" + std::to_string(j), path.empty() ? -1 : path.back(), {}, {}, {}};
    joint.offset = {static_cast<double>(rng() % 2001) / 8 - 125, 0.001 * j, -1.5};
    std::vector<ChannelKind> all = {ChannelKind::kXPosition, ChannelKind::kYPosition,
                                    ChannelKind::kZPosition, ChannelKind::kXRotation,
                                    ChannelKind::kYRotation, ChannelKind::kZRotation};
    std::shuffle(all.begin(), all.end(), rng);
    joint.channels.assign(all.begin(), all.begin() + rng() % 7);
    for (uint64_t e = rng() % 3; e > 0; --e) joint.end_sites.push_back({1.0 / (e + 2), 2, 3});
    clip.skeleton.joints.push_back(joint);
    path.push_back(j);
  }
  clip.frame_time = 1.0 / static_cast<double>(1 + rng() % 240);
  clip.frame_count = static_cast<int>(rng() % 5);
  clip.values.resize(static_cast<size_t>(clip.frame_count) * ChannelCount(clip.skeleton));
  for (double& value : clip.values) {
    do {
      const uint64_t bits = rng();
      std::memcpy(&value, &bits, sizeof value);
    } while (!std::isfinite(value));
  }
  return clip;
}

TEST(WriteBvhTest, RandomClipsRoundTripExactly) {
  std::mt19937_64 rng(99);
  for (int i = 0; i < 300; ++i) {
    const SkeletalClip clip = RandomClip(rng);
    ASSERT_TRUE(ValidateSkeleton(clip.skeleton).ok());
    const std::string written = WriteBvh(clip);
    ASSERT_OK_AND_ASSIGN(const SkeletalClip read, ParseBvh(written));
    ExpectSameClip(clip, read);
    ASSERT_EQ(WriteBvh(read), written);
  }
}

// Each level adds a tab of indentation, so the text grows with depth squared: 3000 levels is about
// 4.5 million tabs.
TEST(WriteBvhTest, WritesADeepChain) {
  constexpr int kDepth = 3000;
  SkeletalClip clip;
  for (int j = 0; j < kDepth; ++j) {
    clip.skeleton.joints.push_back({"j" + std::to_string(j), j - 1, {0, 1, 0}, {}, {}});
  }
  clip.skeleton.joints.back().end_sites.push_back({0, 1, 0});
  clip.frame_time = 1;
  const std::string written = WriteBvh(clip);
  ASSERT_OK_AND_ASSIGN(const SkeletalClip read, ParseBvh(written));
  EXPECT_EQ(read.skeleton.joints.size(), static_cast<size_t>(kDepth));
  EXPECT_EQ(WriteBvh(read), written);
}

}  // namespace
}  // namespace koma::formats

// RetimeCurves' merged key poses and timing groups through an in-process channel: the wire
// bytes the service encodes (fields 20-21 after a file's field 6-7) against the message path,
// Live2D's default grouping applied when the request names none, and groups from the request.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "convert/curves_convert.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "tests/server/in_process_server.h"
#include "tests/testing/live2d_motion.h"

namespace koma::server {
namespace {

using ::testing::ElementsAre;

v1::RetimeCurvesRequest Live2dRequest(double fps, int curves, uint64_t seed) {
  v1::RetimeCurvesRequest request;
  *request.mutable_curves() =
      convert::CurveSetToProto(koma::testing::Live2dMotion({fps, curves, 4.0, seed}));
  return request;
}

// The raw bytes the service answers, parsed, equal the message path's response.
v1::RetimeCurvesResponse CallAndCompare(koma::testing::InProcessServer& server,
                                        const v1::RetimeCurvesRequest& request) {
  std::string bytes;
  const grpc::Status status = koma::testing::RawUnaryCall(
      server, "/koma.v1.Retime/RetimeCurves", request.SerializeAsString(), &bytes);
  EXPECT_TRUE(status.ok()) << status.error_message();
  v1::RetimeCurvesResponse want;
  EXPECT_TRUE(HandleRetimeCurves(request, RequestLimits(), &want).ok());
  EXPECT_EQ(bytes, want.SerializeAsString());  // protobuf's bytes: fields in number order
  v1::RetimeCurvesResponse got;
  EXPECT_TRUE(got.ParseFromString(bytes));
  return got;
}

TEST(CurvesGroupsServiceTest, DefaultGroupingOfStandardIds) {
  koma::testing::InProcessServer server;
  for (double fps : {30.0, 60.0}) {
    const v1::RetimeCurvesResponse response = CallAndCompare(server, Live2dRequest(fps, 50, 3));
    ASSERT_EQ(response.timing_groups_size(), 3);
    EXPECT_EQ(response.timing_groups(0).name(), "body");
    EXPECT_EQ(response.timing_groups(1).name(), "face");
    EXPECT_EQ(response.timing_groups(2).name(), "hair");
    EXPECT_EQ(response.timing_groups(0).timing(), 0);
    for (const v1::CurveTimingGroupResult& group : response.timing_groups()) {
      EXPECT_GT(group.curves_size(), 0) << group.name();
      EXPECT_EQ(group.key_frames_merged_size(), group.key_frames_size());
      for (int c : group.curves()) {
        const std::string& id = response.curves(c).id();
        if (group.name() == "face") {
          EXPECT_TRUE(id.rfind("ParamEye", 0) == 0 || id.rfind("ParamBrow", 0) == 0 ||
                      id.rfind("ParamMouth", 0) == 0 || id == "ParamCheek")
              << id;
        }
        EXPECT_EQ(response.curves(c).timing(), group.timing()) << id;
      }
    }
    EXPECT_THAT(response.key_frames(),
                ::testing::ElementsAreArray(response.timing_groups(0).key_frames()));
    EXPECT_THAT(response.key_frames_merged(),
                ::testing::ElementsAreArray(response.timing_groups(0).key_frames_merged()));
  }
}

// Groups from the request replace the default grouping; the hair on twos gets its own timing.
TEST(CurvesGroupsServiceTest, RequestGroupsAndTheirOwnN) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest request = Live2dRequest(30.0, 60, 5);
  v1::CurveTimingGroup* hair = request.add_timing_groups();
  hair->set_name("hair");
  hair->add_ids("ParamHair*");
  hair->set_frames_per_drawing(2);
  hair->set_tsume(1.5);
  v1::CurveTimingGroup* arms = request.add_timing_groups();
  arms->set_name("arms");
  arms->add_ids("ParamArm*");
  arms->add_ids("ParamHand?");
  arms->add_key_frames(30);
  const v1::RetimeCurvesResponse response = CallAndCompare(server, request);
  ASSERT_EQ(response.timing_groups_size(), 3);
  EXPECT_EQ(response.timing_groups(1).frames_per_drawing(), 2);
  EXPECT_EQ(response.timings(response.timing_groups(1).timing()).frames_per_drawing(), 2);
  EXPECT_THAT(response.timing_groups(2).key_frames(), ElementsAre(0, 30, 120));
  EXPECT_EQ(response.timing_groups(2).key_frames_merged_size(), 0);  // named: not merged
  std::vector<std::string> arm_ids;
  for (int c : response.timing_groups(2).curves()) arm_ids.push_back(response.curves(c).id());
  EXPECT_THAT(arm_ids, ElementsAre("ParamArmLA", "ParamArmLB", "ParamHandL", "ParamArmRA",
                                   "ParamArmRB", "ParamHandR"));
}

// No groups and no merging: the answer of before, with neither field 20 nor 21.
TEST(CurvesGroupsServiceTest, OneGroupUnmergedHasNoNewFields) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest request = Live2dRequest(30.0, 40, 6);
  request.set_default_timing_groups(false);
  request.set_merge_key_poses(false);
  const v1::RetimeCurvesResponse response = CallAndCompare(server, request);
  EXPECT_EQ(response.timing_groups_size(), 0);
  EXPECT_EQ(response.key_frames_merged_size(), 0);
  EXPECT_EQ(response.timings_size(), 1);
}

// A file request: the retimed file (field 6) goes between the grid's fields and 20-21, as
// protobuf orders them, and the groups are those of the decoded request.
TEST(CurvesGroupsServiceTest, FileRequestKeepsFieldOrder) {
  koma::testing::InProcessServer server;
  v1::RetimeCurvesRequest request;
  request.set_csv_text(
      "frame,ParamAngleX,ParamHairFront,ParamEyeLOpen\n0,0,0,1\n1,1,0,1\n2,2,1,0\n3,3,2,0\n"
      "4,4,3,1\n5,5,4,1\n6,6,5,1\n7,7,6,1\n8,8,7,1\n9,9,8,1\n10,10,9,1\n");
  request.set_timing_fps(0.0);
  request.set_frames_per_drawing(2);
  const v1::RetimeCurvesResponse response = CallAndCompare(server, request);
  EXPECT_FALSE(response.csv_text().empty());
  ASSERT_EQ(response.timing_groups_size(), 3);
  EXPECT_THAT(response.timing_groups(1).curves(), ElementsAre(2));  // face: ParamEyeLOpen
  EXPECT_THAT(response.timing_groups(2).curves(), ElementsAre(1));  // hair
}

}  // namespace
}  // namespace koma::server

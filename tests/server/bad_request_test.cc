// Every malformed RetimeSkeletal request gets the right gRPC code and a message naming the
// field and value, through an in-process channel to the real service.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/bad_request_table.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::InProcessServer;
using BadRequest = ::koma::testing::BadRequest<v1::RetimeSkeletalRequest>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

v1::Joint& JointOf(v1::RetimeSkeletalRequest& r, int i) {
  return *r.mutable_motion()->mutable_skeleton()->mutable_joints(i);
}

std::vector<BadRequest> BadRequests() {
  using C = grpc::StatusCode;
  const C kInvalid = C::INVALID_ARGUMENT;
  return {
      {"NoMotion", [](auto& r) { r.clear_motion(); }, kInvalid, "motion: required"},
      {"NoJoints", [](auto& r) { r.mutable_motion()->mutable_skeleton()->clear_joints(); },
       kInvalid, "motion.skeleton.joints: the skeleton has no joints"},
      {"ParentOutOfRange", [](auto& r) { JointOf(r, 1).set_parent(5); }, kInvalid,
       "motion.skeleton.joints[1].parent: 5 is out of range"},
      {"ParentBelowMinusOne", [](auto& r) { JointOf(r, 2).set_parent(-2); }, kInvalid,
       "joints[2].parent: -2"},
      {"ParentCycle", [](auto& r) { JointOf(r, 0).set_parent(0); }, kInvalid,
       "joints[0].parent: 0 forms a cycle"},
      {"ParentCycleOfTwo", [](auto& r) { JointOf(r, 1).set_parent(2); }, kInvalid,
       "joints[1].parent: 2 forms a cycle"},
      {"UnknownChannel", [](auto& r) { JointOf(r, 1).set_channels(2, "Xrot"); }, kInvalid,
       "motion.skeleton.joints[1].channels[2]: unknown channel name \"Xrot\""},
      {"RepeatedChannel", [](auto& r) { JointOf(r, 1).set_channels(2, "Zrotation"); }, kInvalid,
       "joints[1].channels: Zrotation appears twice"},
      {"OffsetNaN", [](auto& r) { JointOf(r, 1).mutable_offset()->set_x(kNaN); }, kInvalid,
       "joints[1].offset"},
      {"FrameTimeZero", [](auto& r) { r.mutable_motion()->set_frame_time(0.0); }, kInvalid,
       "motion.frame_time: 0 s must be finite and > 0"},
      {"FrameTimeNegative", [](auto& r) { r.mutable_motion()->set_frame_time(-0.04); },
       kInvalid, "motion.frame_time: -0.04"},
      {"FrameTimeNaN", [](auto& r) { r.mutable_motion()->set_frame_time(kNaN); }, kInvalid,
       "motion.frame_time: nan"},
      {"OneFrame", [](auto& r) { r.mutable_motion()->set_frame_count(1); }, kInvalid,
       "motion.frame_count: 1 frames, retiming needs at least 2"},
      {"NegativeFrames", [](auto& r) { r.mutable_motion()->set_frame_count(-5); }, kInvalid,
       "motion.frame_count: -5"},
      {"TooFewValues",
       [](auto& r) { r.mutable_motion()->mutable_channels()->mutable_values()->RemoveLast(); },
       kInvalid, "motion.channels.values: expected 120 values (10 frames x 12 channels), got 119"},
      {"NaNValue",
       [](auto& r) { r.mutable_motion()->mutable_channels()->set_values(17, kNaN); }, kInvalid,
       "motion.channels.values[17]: nan is not finite (frame 1, value 5)"},
      {"InfValue",
       [](auto& r) { r.mutable_motion()->mutable_channels()->set_values(0, -kInf); }, kInvalid,
       "motion.channels.values[0]: -inf is not finite"},
      {"NoData", [](auto& r) { r.mutable_motion()->clear_channels(); }, kInvalid,
       "motion.data: neither channels nor positions is set"},
      {"WrongPositionCount",
       [](auto& r) { r.mutable_motion()->mutable_positions()->add_values(1.0); }, kInvalid,
       "motion.positions.values: expected 90 values (10 frames x 3 joints x 3 coordinates), got 1"},
      {"NegativeOmissions", [](auto& r) { r.set_omissions(-1); }, kInvalid, "omissions: -1"},
      {"TooManyOmissions", [](auto& r) { r.set_omissions(8); }, C::OUT_OF_RANGE,
       "omissions: 8"},
      {"NegativeHolds", [](auto& r) { r.set_holds(-2); }, kInvalid, "holds: -2"},
      {"MaxHoldZero", [](auto& r) { r.set_max_hold(0); }, kInvalid, "max_hold: 0"},
      {"CutNeighbourRatioBelowOne", [](auto& r) { r.set_cut_neighbour_ratio(0.5); }, kInvalid,
       "cut_neighbour_ratio: 0.5 must be 0 (no cuts) or a finite ratio >= 1"},
      {"CutNeighbourRatioNaN", [](auto& r) { r.set_cut_neighbour_ratio(kNaN); }, kInvalid,
       "cut_neighbour_ratio: nan"},
      {"CutMedianRatioNegative", [](auto& r) { r.set_cut_median_ratio(-1); }, kInvalid,
       "cut_median_ratio: -1 must be a finite ratio >= 0"},
      {"CutMedianRatioInf", [](auto& r) { r.set_cut_median_ratio(kInf); }, kInvalid,
       "cut_median_ratio: inf"},
      {"OmissionRateNegative", [](auto& r) { r.set_omissions_per_second(-0.5); }, kInvalid,
       "omissions_per_second: -0.5 must be finite and >= 0 (per second)"},
      {"OmissionRateNaN", [](auto& r) { r.set_omissions_per_second(kNaN); }, kInvalid,
       "omissions_per_second: nan"},
      {"OmissionRateWithCount",
       [](auto& r) {
         r.set_omissions(2);
         r.set_omissions_per_second(1);
       },
       kInvalid, "omissions_per_second: 1 given with omissions: 2; give one of the two"},
      {"DrawingRateZero", [](auto& r) { r.set_drawings_per_second(0); }, kInvalid,
       "drawings_per_second: 0 must be finite and > 0 (per second)"},
      {"DrawingRateInf", [](auto& r) { r.set_drawings_per_second(kInf); }, kInvalid,
       "drawings_per_second: inf"},
      {"UnknownOrder", [](auto& r) { r.set_order(static_cast<v1::StepOrder>(9)); }, kInvalid,
       "order: 9 is not a StepOrder"},
      {"CameraShort", [](auto& r) { for (int i = 0; i < 15; ++i) r.add_camera(1.0); },
       kInvalid, "camera: 15 values, a 4x4 matrix needs 16"},
      {"CameraNaN",
       [](auto& r) {
         for (int i = 0; i < 16; ++i) r.add_camera(i == 3 ? kNaN : 1.0);
       },
       kInvalid, "camera[3]: nan is not finite"},
      {"CameraZeroW", [](auto& r) { for (int i = 0; i < 16; ++i) r.add_camera(0.0); },
       kInvalid, "camera"},
      {"PositionsTooLargeForTheDistance",
       [](auto& r) { JointOf(r, 2).mutable_offset()->set_x(1e200); }, C::OUT_OF_RANGE,
       "motion: positions: largest |coordinate| 1e+200"},
      {"ForwardKinematicsOverflows",
       [](auto& r) {
         JointOf(r, 1).mutable_offset()->set_x(1.5e308);
         JointOf(r, 2).mutable_offset()->set_x(1.5e308);
       },
       kInvalid, "is not finite (frame 0 joint 2 x)"},
      {"WeightsCount", [](auto& r) { r.add_joint_weights(1.0); r.add_joint_weights(1.0); },
       kInvalid, "joint_weights: 2 weights for 3 joints"},
      {"WeightNegative",
       [](auto& r) { for (double w : {1.0, -1.0, 1.0}) r.add_joint_weights(w); }, kInvalid,
       "joint_weights[1]: -1 must be finite and >= 0"},
      {"WeightInf",
       [](auto& r) { for (double w : {1.0, 1.0, kInf}) r.add_joint_weights(w); }, kInvalid,
       "joint_weights[2]: inf"},
      {"OverValueLimit", [](auto& r) {
         auto* motion = r.mutable_motion();
         motion->set_frame_count(5000);
         motion->mutable_channels()->mutable_values()->Resize(5000 * 12, 0.0);
       },
       C::RESOURCE_EXHAUSTED, "exceeds the server limit --max_values=50000"},
      {"OverJointLimit", [](auto& r) {
         auto* skeleton = r.mutable_motion()->mutable_skeleton();
         for (int i = 0; i < 40; ++i) skeleton->add_joints()->set_parent(0);
       },
       C::RESOURCE_EXHAUSTED, "43 joints exceeds the server limit --max_joints=32"},
  };
}

class BadRequestTest
    : public koma::testing::BadRequestSuite<BadRequestTest, v1::RetimeSkeletalRequest> {
 public:
  static server::ServerConfig SuiteConfig() {
    server::ServerConfig config = InProcessServer::Config(2, 50'000);
    config.limits.max_joints = 32;
    return config;
  }
  static v1::RetimeSkeletalRequest ValidRequest() { return koma::testing::MakeSkeletalRequest(10); }
};

KOMA_BAD_REQUEST_TABLE(BadRequestTest, BadRequestTableTest, BadRequests)

}  // namespace
}  // namespace koma::server

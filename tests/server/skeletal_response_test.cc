// The RetimeSkeletal wire encoder (server/skeletal_response.h) against the message path:
// RetimeSkeletalAnswer's bytes must equal HandleRetimeSkeletal's response serialised by
// protobuf, for either data form, with and without the motion, and across the sizes where the
// length prefixes grow a byte.
#include "server/skeletal_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/split_mix64.h"
#include "server/request_limits.h"
#include "server/skeletal_request.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

std::string Bytes(const grpc::Slice& slice) {
  return std::string(reinterpret_cast<const char*>(slice.begin()), slice.size());
}

// A valid request of the channel form (the builder's 3-joint swing) or of world positions
// (1-6 joints), with random retiming options and motion fields.
v1::RetimeSkeletalRequest RandomRequest(SplitMix64& rng) {
  const bool positions = rng.OneIn(2);
  // Up to 3,000 frames now and then: the values' length prefix passes 2 and 3 bytes.
  const int frames = rng.OneIn(5) ? rng.Int(600, 3000) : rng.Int(2, 150);
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(frames);
  v1::SkeletalMotion* motion = request.mutable_motion();
  if (positions) {
    const int joints = rng.Int(1, 3);
    while (motion->skeleton().joints_size() > joints) {
      motion->mutable_skeleton()->mutable_joints()->RemoveLast();
    }
    auto* values = motion->mutable_positions()->mutable_values();  // replaces the channels
    for (int k = 0; k < frames * joints * 3; ++k) {
      values->Add(rng.OneIn(4) ? 0.0 : 50.0 * (rng.Unit() - 0.5));
    }
  }
  const double frame_times[] = {1.0 / 24.0, 1.0 / 30.0, 0.001, 1.0};
  motion->set_frame_time(frame_times[rng.Int(0, 3)]);
  if (rng.OneIn(2)) request.set_omissions(rng.Int(0, frames / 4));
  if (rng.OneIn(2)) request.set_holds(rng.Int(0, frames / 2));
  if (rng.OneIn(3)) request.set_max_hold(rng.Int(1, 4));
  if (rng.OneIn(3)) request.set_keep_length(rng.OneIn(2));
  if (rng.OneIn(3)) request.set_return_motion(rng.OneIn(2));
  if (rng.OneIn(4)) request.set_root_relative(true);
  // The film grid: unset (24), off, or another rate; its fields follow the motion.
  if (rng.OneIn(3)) request.set_timing_fps(rng.OneIn(2) ? 0.0 : 12.0 * rng.Int(1, 10));
  if (rng.OneIn(3)) request.set_output_rate(rng.OneIn(2) ? v1::TIMING_RATE : v1::SOURCE_RATE);
  return request;
}

TEST(SkeletalResponseTest, BytesEqualTheMessagePathOnRandomRequests) {
  SplitMix64 rng(2026);
  const RequestLimits limits;
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    const v1::RetimeSkeletalRequest request = RandomRequest(rng);
    v1::RetimeSkeletalResponse message;
    const absl::Status message_status = HandleRetimeSkeletal(request, limits, &message);
    SkeletalAnswer answer;
    const absl::Status answer_status = RetimeSkeletalAnswer(request, limits, &answer);
    ASSERT_EQ(answer_status, message_status) << "request " << i;
    if (!answer_status.ok()) continue;
    ASSERT_EQ(Bytes(answer.bytes), message.SerializeAsString())
        << "request " << i << ": " << request.motion().frame_count() << " frames, "
        << (request.motion().has_positions() ? "positions" : "channels") << ", return_motion "
        << (!request.has_return_motion() || request.return_motion());
    ++compared;
  }
  EXPECT_GE(compared, 250);  // nearly every random request is valid
}

// return_motion false: the response is every other field, no motion at all.
TEST(SkeletalResponseTest, WithoutTheMotionTheBytesAreTheHeadAlone) {
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(20);
  request.set_return_motion(false);
  v1::RetimeSkeletalResponse message;
  ASSERT_TRUE(HandleRetimeSkeletal(request, RequestLimits(), &message).ok());
  EXPECT_FALSE(message.has_motion());
  SkeletalAnswer answer;
  ASSERT_TRUE(RetimeSkeletalAnswer(request, RequestLimits(), &answer).ok());
  EXPECT_EQ(Bytes(answer.bytes), message.SerializeAsString());
}

// The encoder alone: exactly size() bytes (a guard after them stays untouched), frames in any
// order and repeated, and a frame time of +0.0 (left out), -0.0 (written) or neither.
TEST(SkeletalResponseTest, TheEncoderWritesExactlyItsSize) {
  const v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(40);
  v1::RetimeSkeletalResponse head;
  head.add_source_frames(0);
  head.add_source_frames(39);
  head.add_input_ssd(-0.0);
  head.set_max_hold(3);
  const std::vector<int32_t> frames = {0, 39, 39, 7};
  v1::SkeletalMotion motion = request.motion();
  for (const double frame_time : {0.0, -0.0, 1.0 / 24.0}) {
    motion.set_frame_time(frame_time);
    v1::RetimeSkeletalResponse tail;
    tail.set_timing_fps(24);
    tail.add_grid_frames(0);
    tail.add_grid_frames(1);
    tail.set_duplicates_omitted(1);  // fields 50 and 51 after the grid's
    tail.set_duplicates_held(2);
    const SkeletalResponseEncoder encoder(head, tail, true, motion, motion.frame_time(), true, 12,
                                          frames);
    std::string out(encoder.size() + 16, '\x5a');  // a guard after the end
    encoder.WriteTo(reinterpret_cast<uint8_t*>(out.data()));
    EXPECT_EQ(out.substr(encoder.size()), std::string(16, '\x5a')) << frame_time;
    v1::RetimeSkeletalResponse want = head;
    v1::SkeletalMotion* want_motion = want.mutable_motion();
    *want_motion->mutable_skeleton() = motion.skeleton();
    want_motion->set_frame_time(frame_time);
    want_motion->set_frame_count(4);
    for (const int32_t f : frames) {
      for (int c = 0; c < 12; ++c) {
        want_motion->mutable_channels()->add_values(motion.channels().values(f * 12 + c));
      }
    }
    want.MergeFrom(tail);
    EXPECT_EQ(out.substr(0, encoder.size()), want.SerializeAsString()) << frame_time;
  }
}

}  // namespace
}  // namespace koma::server

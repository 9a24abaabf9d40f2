// The handler answers every request, however mangled: OK or a clean error, never a crash,
// hang or non-finite number in an answer. Seeded byte and field mutations of valid requests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "core/split_mix64.h"
#include "server/skeletal_request.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

void ExpectWellFormedAnswer(const v1::RetimeSkeletalRequest& request, uint64_t seed) {
  RequestLimits limits;
  limits.max_values = 200'000;
  v1::RetimeSkeletalResponse response;
  const absl::Status status = HandleRetimeSkeletal(request, limits, &response);
  if (!status.ok()) {
    EXPECT_FALSE(status.message().empty()) << "seed " << seed;
    EXPECT_NE(status.code(), absl::StatusCode::kInternal) << "seed " << seed << ": " << status;
    return;
  }
  const int n = request.motion().frame_count();
  for (int32_t source : response.source_frames()) {
    ASSERT_TRUE(source >= 0 && source < n) << "seed " << seed;
  }
  for (double ssd : response.input_ssd()) ASSERT_TRUE(std::isfinite(ssd)) << "seed " << seed;
}

TEST(HandlerRobustnessTest, MangledBytesNeverCrash) {
  const std::string valid = koma::testing::MakeSkeletalRequest(12).SerializeAsString();
  for (uint64_t seed = 0; seed < 3000; ++seed) {
    SplitMix64 random(seed);
    std::string bytes = valid;
    const int flips = 1 + random.Int(0, 7);
    for (int i = 0; i < flips; ++i) {
      bytes[random.Int(0, static_cast<int>(bytes.size()) - 1)] = static_cast<char>(random.Next());
    }
    v1::RetimeSkeletalRequest request;
    if (!request.ParseFromString(bytes)) continue;  // gRPC would reject it before us
    ExpectWellFormedAnswer(request, seed);
  }
}

TEST(HandlerRobustnessTest, ExtremeFieldValuesNeverCrash) {
  const int32_t extremes[] = {INT32_MIN, -1, 0, 1, 2, 3, 7, 11, 12, 13, 1000, INT32_MAX};
  for (uint64_t seed = 0; seed < 2000; ++seed) {
    SplitMix64 random(seed);
    v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(12);
    auto pick = [&] { return extremes[random.Int(0, 11)]; };
    switch (random.Int(0, 5)) {
      case 0: request.mutable_motion()->set_frame_count(pick()); break;
      case 1: request.mutable_motion()->mutable_skeleton()->mutable_joints(random.Int(0, 2))
                  ->set_parent(pick()); break;
      case 2: request.set_max_hold(pick()); break;
      default: break;
    }
    if (random.Int(0, 1) == 0) request.set_omissions(pick());
    if (random.Int(0, 1) == 0) request.set_holds(pick());
    if (random.Int(0, 2) == 0) request.set_keep_length(false);
    if (random.Int(0, 2) == 0) request.set_order(v1::HOLD_THEN_OMIT);
    if (random.Int(0, 3) == 0) request.set_root_relative(true);
    ExpectWellFormedAnswer(request, seed);
  }
}

}  // namespace
}  // namespace koma::server

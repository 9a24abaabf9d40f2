// LipBlink through an in-process channel: the answer's shape, linked eyes, and the same bytes
// for the same seed across runs, thread counts and machines (a golden hash).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/lip_blink_request.h"
#include "server/request_limits.h"
#include "server/server.h"
#include "tests/server/in_process_server.h"
#include "tests/server/lip_blink_request_builder.h"
#include "tests/testing/fnv1a.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;

using ::koma::testing::Fnv1a64;

TEST(LipBlinkServiceTest, ConvertsMouthAndLinkedEyesAndLeavesOtherCurvesOut) {
  koma::testing::InProcessServer server;
  v1::Retime::Stub& stub = server.stub();
  v1::LipBlinkResponse response;
  ASSERT_TRUE(CallRpc(stub, koma::testing::MakeLipBlinkRequest(), &response).ok());

  ASSERT_EQ(response.mouths_size(), 1);
  ASSERT_EQ(response.eyes_size(), 2);
  ASSERT_EQ(response.curves_size(), 3);  // ParamAngleX is not returned
  EXPECT_EQ(response.curves(0).id(), "ParamMouthOpenY");
  EXPECT_EQ(response.seed(), 0x6b6f6d61u);

  const v1::MouthTrack& mouth = response.mouths(0);
  ASSERT_GE(mouth.speech_size(), 1);
  std::set<double> levels;
  for (const v1::FrameInterval& speech : mouth.speech()) {
    for (int f = speech.begin(); f < speech.end(); ++f) levels.insert(response.curves(0).values(f));
  }
  EXPECT_LE(levels.size(), 3u);
  for (int h = 1; h < mouth.holds_size(); ++h) {
    if (mouth.holds(h).begin() == mouth.holds(h - 1).begin() + mouth.holds(h - 1).length()) {
      EXPECT_NE(mouth.holds(h).shape(), mouth.holds(h - 1).shape()) << "hold " << h;
    }
  }

  // Linked eyes: the same blinks, closed on the same frames.
  ASSERT_EQ(response.eyes(0).blinks_size(), 1);
  ASSERT_EQ(response.eyes(1).blinks_size(), 1);
  EXPECT_EQ(response.eyes(0).blinks(0).SerializeAsString(),
            response.eyes(1).blinks(0).SerializeAsString());
  for (int f = 0; f < 60; ++f) {
    const bool left_closed = response.curves(1).values(f) == response.eyes(0).closed_level();
    const bool right_closed = response.curves(2).values(f) == response.eyes(1).closed_level();
    EXPECT_EQ(left_closed, right_closed) << "frame " << f;
  }
}

TEST(LipBlinkServiceTest, SameSeedSameBytesAcrossRunsAndThreadCounts) {
  v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
  request.set_seed(2024);
  request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.5);
  request.set_timing_fps(0.0);  // pinned from before the film grid: counted in source frames
  std::vector<std::string> answers;
  for (int threads : {1, 2, 4}) {
    koma::testing::InProcessServer server(
        koma::testing::InProcessServer::Config(threads, RequestLimits{}.max_values));
    v1::Retime::Stub& stub = server.stub();
    std::vector<std::string> bytes(6);
    std::vector<std::thread> clients;
    for (size_t i = 0; i < bytes.size(); ++i) {
      clients.emplace_back([&, i] {
        v1::LipBlinkResponse response;
        if (CallRpc(stub, request, &response).ok()) bytes[i] = response.SerializeAsString();
      });
    }
    for (std::thread& client : clients) client.join();
    answers.insert(answers.end(), bytes.begin(), bytes.end());
  }
  ASSERT_FALSE(answers.front().empty());
  for (const std::string& answer : answers) EXPECT_EQ(answer, answers.front());
  // Golden: computed once here and checked in. A machine, compiler or standard library that
  // answers differently fails this line, which is the point.
  EXPECT_EQ(Fnv1a64(answers.front()), 0x4c543fd8830607b5ULL)
      << std::hex << Fnv1a64(answers.front());
}

// The same 30 fps request on the default 24 fps film grid, pinned; and the curves declared at
// 24 fps answer exactly what they answer with no grid (timing_fps 0).
TEST(LipBlinkServiceTest, FilmGridAnswersArePinned) {
  koma::testing::InProcessServer server;
  v1::Retime::Stub& stub = server.stub();
  v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
  request.set_seed(2024);
  request.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
  request.mutable_eyes()->mutable_auto_blink()->set_mean_interval_s(0.5);
  v1::LipBlinkResponse grid;
  ASSERT_TRUE(CallRpc(stub, request, &grid).ok());
  EXPECT_EQ(grid.timing_fps(), 24.0);
  EXPECT_EQ(Fnv1a64(grid.SerializeAsString()), 0xc7235ecc3e5e0ccfULL)
      << std::hex << Fnv1a64(grid.SerializeAsString());
  request.mutable_curves()->set_fps(24.0);
  v1::LipBlinkResponse at24;
  ASSERT_TRUE(CallRpc(stub, request, &at24).ok());
  request.set_timing_fps(0.0);
  v1::LipBlinkResponse no_grid;
  ASSERT_TRUE(CallRpc(stub, request, &no_grid).ok());
  EXPECT_EQ(at24.timing_fps(), 0.0);
  EXPECT_EQ(at24.SerializeAsString(), no_grid.SerializeAsString());
}

TEST(LipBlinkServiceTest, AnotherSeedGivesAnotherMouth) {
  koma::testing::InProcessServer server;
  v1::Retime::Stub& stub = server.stub();
  std::set<std::string> shapes;
  for (uint64_t seed : {1, 2, 3, 4}) {
    v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
    request.set_seed(seed);
    v1::LipBlinkResponse response;
    ASSERT_TRUE(CallRpc(stub, request, &response).ok());
    std::string sequence;
    for (const v1::MouthHold& hold : response.mouths(0).holds())
      sequence += char('0' + hold.shape());
    shapes.insert(sequence);
  }
  EXPECT_GT(shapes.size(), 1u);
}

// A request of 1 MiB or more is parsed from one contiguous copy of the received bytes
// (retime_service.cc): the answer is the same as the handler's on the message itself, and
// bytes of that size that are not a LipBlinkRequest are refused by name.
TEST(LipBlinkServiceTest, LargeRequestParsedInOnePieceGivesTheHandlersAnswer) {
  v1::LipBlinkRequest request = koma::testing::MakeLipBlinkRequest();
  constexpr int kFrames = 60000;  // 4 curves x 60,000 samples x 8 bytes: ~1.9 MB
  request.mutable_curves()->set_frame_count(kFrames);
  for (v1::Curve& curve : *request.mutable_curves()->mutable_curves()) {
    const std::vector<double> first(curve.samples().begin(), curve.samples().end());
    curve.clear_samples();
    for (int f = 0; f < kFrames; ++f) curve.add_samples(first[f % first.size()]);
  }
  ASSERT_GE(request.ByteSizeLong(), size_t{1} << 20);
  v1::LipBlinkResponse expected;
  ASSERT_TRUE(HandleLipBlink(request, RequestLimits(), &expected).ok());

  koma::testing::InProcessServer server;
  std::string answer;
  ASSERT_TRUE(koma::testing::RawUnaryCall(server, "/koma.v1.Retime/LipBlink",
                                          request.SerializeAsString(), &answer)
                  .ok());
  EXPECT_EQ(answer, expected.SerializeAsString());

  const std::string garbage(size_t{3} << 19, '\xff');  // 1.5 MiB, no valid tag
  const grpc::Status refused =
      koma::testing::RawUnaryCall(server, "/koma.v1.Retime/LipBlink", garbage, &answer);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(refused.error_message(), ::testing::HasSubstr("not a valid koma.v1.LipBlinkRequest"));
}

}  // namespace
}  // namespace koma::server

#include "server/idle_trim.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/server/curves_request_builder.h"
#include "tests/server/in_process_server.h"

namespace koma::server {
namespace {

using std::chrono::milliseconds;

// Polls `condition` every 5 ms for up to 5 s.
template <typename Condition>
bool Eventually(Condition condition) {
  for (int i = 0; i < 1000; ++i) {
    if (condition()) return true;
    std::this_thread::sleep_for(milliseconds(5));
  }
  return condition();
}

TEST(IdleTrimmerTest, TrimsOnceWhenIdleAfterEnoughRequestBytes) {
  IdleTrimmer trimmer(absl::Milliseconds(10), 100);
  trimmer.CallStarted(150);
  trimmer.CallFinished();
  EXPECT_TRUE(Eventually([&] { return trimmer.trims() == 1; }));
  // Nothing new arrived: no second trim.
  std::this_thread::sleep_for(milliseconds(100));
  EXPECT_EQ(trimmer.trims(), 1);
  // New bytes, another quiet period: a second one.
  trimmer.CallStarted(100);
  trimmer.CallFinished();
  EXPECT_TRUE(Eventually([&] { return trimmer.trims() == 2; }));
}

TEST(IdleTrimmerTest, NeverWhileACallIsInFlight) {
  IdleTrimmer trimmer(absl::Milliseconds(10), 0);
  trimmer.CallStarted(1 << 30);
  std::this_thread::sleep_for(milliseconds(150));  // fifteen periods
  EXPECT_EQ(trimmer.trims(), 0);
  trimmer.CallFinished();
  // At least one: with no byte threshold it trims every quiet period, and a slow run (TSan)
  // can poll past the moment the count is exactly 1.
  EXPECT_TRUE(Eventually([&] { return trimmer.trims() >= 1; }));
}

TEST(IdleTrimmerTest, NotAfterSmallCalls) {
  IdleTrimmer trimmer(absl::Milliseconds(10), 1000);
  for (int i = 0; i < 9; ++i) {
    trimmer.CallStarted(100);
    trimmer.CallFinished();
  }
  std::this_thread::sleep_for(milliseconds(150));
  EXPECT_EQ(trimmer.trims(), 0);
  trimmer.CallStarted(100);  // the tenth makes 1000 bytes
  trimmer.CallFinished();
  EXPECT_TRUE(Eventually([&] { return trimmer.trims() == 1; }));
}

TEST(IdleTrimmerTest, WaitsForAWholeQuietPeriod) {
  // Calls keep starting every 20 ms for 300 ms: no period of 100 ms is quiet until they stop.
  IdleTrimmer trimmer(absl::Milliseconds(100), 0);
  for (int i = 0; i < 15; ++i) {
    trimmer.CallStarted(1);
    trimmer.CallFinished();
    std::this_thread::sleep_for(milliseconds(20));
  }
  EXPECT_EQ(trimmer.trims(), 0);
  EXPECT_TRUE(Eventually([&] { return trimmer.trims() == 1; }));
}

TEST(IdleTrimmerTest, ZeroIdleIsOff) {
  IdleTrimmer trimmer(absl::ZeroDuration(), 0);
  trimmer.CallStarted(1 << 30);
  trimmer.CallFinished();
  std::this_thread::sleep_for(milliseconds(50));
  EXPECT_EQ(trimmer.trims(), 0);
}

// The server counts its calls into the trimmer: one RetimeCurves call, then quiet.
TEST(IdleTrimmerTest, TheServerTrimsAfterItsCalls) {
  ServerConfig config;
  config.idle_trim = absl::Milliseconds(10);
  config.idle_trim_min_request_bytes = 1;
  testing::InProcessServer server(config);
  EXPECT_EQ(server.server().idle_trims(), 0);
  grpc::ClientContext context;
  testing::SetTestDeadline(context);
  v1::RetimeCurvesResponse response;
  ASSERT_TRUE(
      server.stub().RetimeCurves(&context, testing::MakeCurvesRequest(), &response).ok());
  EXPECT_TRUE(Eventually([&] { return server.server().idle_trims() == 1; }));
}

}  // namespace
}  // namespace koma::server

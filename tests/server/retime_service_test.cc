// The Retime service through an in-process channel: answers, determinism, limits, health.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "grpc/health/v1/health.grpc.pb.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;

using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::unique_ptr<KomaServer> StartInProcess(int worker_threads, int max_message_bytes = 0) {
  ServerConfig config;
  config.address = "";
  config.worker_threads = worker_threads;
  if (max_message_bytes > 0) config.max_message_bytes = max_message_bytes;
  return KomaServer::Start(config).value();
}

TEST(RetimeServiceTest, RetimesAndCopiesSourceFramesVerbatim) {
  auto server = StartInProcess(2);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(30);
  request.set_max_hold(3);  // a count named: the paper's defaults for the others
  v1::RetimeSkeletalResponse response;
  ASSERT_TRUE(CallRpc(*stub, request, &response).ok());

  ASSERT_EQ(response.source_frames_size(), 30);  // keep_length by default
  EXPECT_EQ(response.source_frames(0), 0);
  EXPECT_EQ(response.source_frames(29), 29);
  EXPECT_EQ(response.omissions_requested(), 4);
  EXPECT_EQ(response.holds_requested(), 10);  // 30 / 3
  EXPECT_EQ(response.max_hold(), 3);
  EXPECT_EQ(response.omissions_applied(), 4);
  EXPECT_EQ(response.input_ssd_size(), 30);
  EXPECT_EQ(response.input_ssd(0), 0.0);
  const v1::SkeletalMotion& out = response.motion();
  EXPECT_EQ(out.frame_count(), 30);
  EXPECT_EQ(out.frame_time(), request.motion().frame_time());
  EXPECT_EQ(out.skeleton().SerializeAsString(), request.motion().skeleton().SerializeAsString());
  const auto& in_values = request.motion().channels().values();
  const auto& out_values = out.channels().values();
  ASSERT_EQ(out_values.size(), 30 * 12);
  for (int t = 0; t < 30; ++t) {
    for (int c = 0; c < 12; ++c) {
      ASSERT_EQ(out_values[t * 12 + c], in_values[response.source_frames(t) * 12 + c])
          << "output frame " << t << " channel " << c;
    }
  }
}

TEST(RetimeServiceTest, ExplicitParametersAndNoMotion) {
  auto server = StartInProcess(1);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(12);
  request.set_omissions(2);
  request.set_holds(0);
  request.set_keep_length(false);
  request.set_return_motion(false);
  v1::RetimeSkeletalResponse response;
  ASSERT_TRUE(CallRpc(*stub, request, &response).ok());
  EXPECT_EQ(response.source_frames_size(), 10);  // 12 - 2 omissions
  EXPECT_EQ(response.deleted_frames_size(), 2);
  EXPECT_EQ(response.holds_applied(), 0);
  EXPECT_FALSE(response.has_motion());
}

TEST(RetimeServiceTest, PositionsFormAnswersInPositionsForm) {
  auto server = StartInProcess(1);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(8);
  auto* positions = request.mutable_motion()->mutable_positions()->mutable_values();
  for (int f = 0; f < 8; ++f) {
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) positions->Add(f * f * (j + 1) + k);  // accelerating
    }
  }
  request.set_omissions(1);
  request.set_holds(0);
  v1::RetimeSkeletalResponse response;
  ASSERT_TRUE(CallRpc(*stub, request, &response).ok());
  // The fastest inner frame is the last inner one (speed grows with f): frame 6 goes.
  EXPECT_THAT(response.deleted_frames(), ElementsAre(6));
  ASSERT_TRUE(response.motion().has_positions());
  EXPECT_EQ(response.motion().positions().values_size(), 8 * 9);
}

TEST(RetimeServiceTest, SameRequestSameBytesWhateverTheThreadCount) {
  const v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(200);
  std::vector<std::string> answers;
  for (int threads : {1, 2, 4}) {
    auto server = StartInProcess(threads);
    auto stub = v1::Retime::NewStub(server->InProcessChannel());
    std::vector<std::string> bytes(6);
    std::vector<std::thread> clients;
    for (size_t i = 0; i < bytes.size(); ++i) {
      clients.emplace_back([&, i] {
        v1::RetimeSkeletalResponse response;
        if (CallRpc(*stub, request, &response).ok()) bytes[i] = response.SerializeAsString();
      });
    }
    for (std::thread& client : clients) client.join();
    for (const std::string& b : bytes) answers.push_back(b);
  }
  ASSERT_FALSE(answers.front().empty());
  for (const std::string& answer : answers) EXPECT_EQ(answer, answers.front());
}

std::string ServerRequestId(const grpc::ClientContext& context) {
  const auto& metadata = context.GetServerInitialMetadata();
  const auto found = metadata.find("x-request-id");
  return found == metadata.end() ? "" : std::string(found->second.data(), found->second.size());
}

TEST(RetimeServiceTest, RequestIdIsEchoedOrGenerated) {
  auto server = StartInProcess(1);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  const v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(10);
  v1::RetimeSkeletalResponse response;
  {
    grpc::ClientContext context;
    context.AddMetadata("x-request-id", "render-farm-job-42");
    ASSERT_TRUE(stub->RetimeSkeletal(&context, request, &response).ok());
    EXPECT_EQ(ServerRequestId(context), "render-farm-job-42");
  }
  std::string first;
  for (int i = 0; i < 2; ++i) {
    grpc::ClientContext context;
    ASSERT_TRUE(stub->RetimeSkeletal(&context, request, &response).ok());
    const std::string generated = ServerRequestId(context);
    EXPECT_EQ(generated.size(), 16u);
    EXPECT_EQ(generated.find_first_not_of("0123456789abcdef"), std::string::npos) << generated;
    if (i == 0) {
      first = generated;
    } else {
      EXPECT_NE(generated, first);
    }
  }
}

TEST(RetimeServiceTest, RequestOverMaxMessageBytesIsResourceExhausted) {
  auto server = StartInProcess(1, /*max_message_bytes=*/64 * 1024);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  const v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(1000);  // ~96 KB
  v1::RetimeSkeletalResponse response;
  EXPECT_EQ(CallRpc(*stub, request, &response).error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST(RetimeServiceTest, HealthIsServingOverLoopbackThenGoneAfterShutdown) {
  ServerConfig config;
  config.address = "127.0.0.1:0";
  config.worker_threads = 1;
  auto server = KomaServer::Start(config).value();
  ASSERT_GT(server->port(), 0);
  auto channel = grpc::CreateChannel("127.0.0.1:" + std::to_string(server->port()),
                                     grpc::InsecureChannelCredentials());
  auto health = grpc::health::v1::Health::NewStub(channel);
  for (const char* service : {"", "koma.v1.Retime"}) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
    grpc::health::v1::HealthCheckRequest request;
    request.set_service(service);
    grpc::health::v1::HealthCheckResponse response;
    ASSERT_TRUE(health->Check(&context, request, &response).ok());
    EXPECT_EQ(response.status(), grpc::health::v1::HealthCheckResponse::SERVING) << service;
  }
  server->Shutdown(absl::Milliseconds(100));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = health->Check(&context, {}, &response);
  EXPECT_FALSE(status.ok() &&
               response.status() == grpc::health::v1::HealthCheckResponse::SERVING);
}

}  // namespace
}  // namespace koma::server

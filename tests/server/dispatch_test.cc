// Where RetimeService runs a call: small requests inline on gRPC's callback thread, larger
// ones on the worker pool, whose bounded queue answers RESOURCE_EXHAUSTED when full.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <future>
#include <memory>
#include <string>

#include "server/retime_service.h"
#include "server/worker_pool.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

// A service on `pool` behind an in-process gRPC server.
class ServiceUnderTest {
 public:
  ServiceUnderTest(WorkerPool* pool, int64_t inline_max_bytes)
      : service_(RequestLimits{}, pool, nullptr, inline_max_bytes) {
    grpc::ServerBuilder builder;
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    stub_ = v1::Retime::NewStub(server_->InProcessChannel(grpc::ChannelArguments()));
  }
  ~ServiceUnderTest() { server_->Shutdown(); }

  grpc::Status Call(const v1::RetimeSkeletalRequest& request,
                    v1::RetimeSkeletalResponse* response) {
    grpc::ClientContext context;
    testing::SetTestDeadline(context);
    return stub_->RetimeSkeletal(&context, request, response);
  }

 private:
  RetimeService service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Retime::Stub> stub_;
};

// A pool of one worker and a queue of one, both taken until the test ends: every call
// handed to it is refused.
class DispatchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::promise<void> started;
    ASSERT_EQ(pool_.TrySubmit([this, &started] {
      started.set_value();
      release_.get_future().wait();
    }),
              WorkerPool::Submission::kAccepted);
    started.get_future().wait();  // the worker is busy,
    ASSERT_EQ(pool_.TrySubmit([] {}), WorkerPool::Submission::kAccepted);  // the queue is full
    ASSERT_EQ(pool_.TrySubmit([] {}), WorkerPool::Submission::kQueueFull);
  }
  void TearDown() override { release_.set_value(); }

  std::promise<void> release_;
  WorkerPool pool_{1, 1};
};

TEST_F(DispatchTest, SmallRequestsRunInlineEvenWhenThePoolIsFull) {
  ServiceUnderTest service(&pool_, RetimeService::kDefaultInlineMaxBytes);
  v1::RetimeSkeletalResponse response;
  const grpc::Status status = service.Call(testing::MakeSkeletalRequest(), &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(response.source_frames_size(), 10);
}

TEST_F(DispatchTest, RequestsAboveTheInlineLimitQueueAndAreRefusedWhenFull) {
  ServiceUnderTest service(&pool_, /*inline_max_bytes=*/0);
  v1::RetimeSkeletalResponse response;
  const grpc::Status status = service.Call(testing::MakeSkeletalRequest(), &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(status.error_message().find("--max_queued"), std::string::npos)
      << status.error_message();
  EXPECT_EQ(response.source_frames_size(), 0);
}

// Inline and pooled calls give the same bytes.
TEST(DispatchEqualityTest, InlineAndPooledAnswersAreIdentical) {
  WorkerPool pool(2, 8);
  ServiceUnderTest inline_service(&pool, RetimeService::kDefaultInlineMaxBytes);
  ServiceUnderTest pooled_service(&pool, 0);
  const v1::RetimeSkeletalRequest request = testing::MakeSkeletalRequest(40);
  v1::RetimeSkeletalResponse inline_response, pooled_response;
  ASSERT_TRUE(inline_service.Call(request, &inline_response).ok());
  ASSERT_TRUE(pooled_service.Call(request, &pooled_response).ok());
  EXPECT_EQ(inline_response.SerializeAsString(), pooled_response.SerializeAsString());
}

}  // namespace
}  // namespace koma::server

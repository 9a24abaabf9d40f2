// A real koma server with no listening port, reached through its in-process channel.
#ifndef KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_
#define KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"

namespace koma::testing {

class InProcessServer {
 public:
  // `config.address` is ignored: no port is opened.
  explicit InProcessServer(server::ServerConfig config = {}) {
    config.address = "";
    server_ = server::KomaServer::Start(config).value();
    stub_ = v1::Retime::NewStub(server_->InProcessChannel());
  }
  static server::ServerConfig Config(int worker_threads, int64_t max_values) {
    server::ServerConfig config;
    config.worker_threads = worker_threads;
    config.limits.max_values = max_values;
    return config;
  }

  server::KomaServer& server() { return *server_; }
  v1::Retime::Stub& stub() { return *stub_; }

 private:
  std::unique_ptr<server::KomaServer> server_;
  std::unique_ptr<v1::Retime::Stub> stub_;
};

// A parameterised suite (a table of bad requests, say) whose cases share one InProcessServer,
// started once for the suite with `Derived::SuiteConfig()` rather than once per case.
//   class BadThingTest : public SharedServerTest<BadThingTest, BadThing> {
//    public:
//     static server::ServerConfig SuiteConfig() { return InProcessServer::Config(1, 50'000); }
//   };
template <typename Derived, typename Param>
class SharedServerTest : public ::testing::TestWithParam<Param> {
 protected:
  static void SetUpTestSuite() { shared_ = new InProcessServer(Derived::SuiteConfig()); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }
  static v1::Retime::Stub& stub() { return shared_->stub(); }

 private:
  static inline InProcessServer* shared_ = nullptr;
};

// Every test RPC gets a deadline, so a broken server fails a test instead of hanging it.
inline void SetTestDeadline(grpc::ClientContext& context, int seconds = 30) {
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
}

// The answer type of each RPC, by its request type.
template <typename Request>
struct ResponseOfRpc;
template <>
struct ResponseOfRpc<v1::RetimeSkeletalRequest> {
  using type = v1::RetimeSkeletalResponse;
};
template <>
struct ResponseOfRpc<v1::RetimeCurvesRequest> {
  using type = v1::RetimeCurvesResponse;
};
template <>
struct ResponseOfRpc<v1::LipBlinkRequest> {
  using type = v1::LipBlinkResponse;
};
template <typename Request>
using ResponseOf = typename ResponseOfRpc<Request>::type;

// One call of the RPC that takes `request`, with the test deadline.
inline grpc::Status CallRpc(v1::Retime::Stub& stub, const v1::RetimeSkeletalRequest& request,
                            v1::RetimeSkeletalResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return stub.RetimeSkeletal(&context, request, response);
}
inline grpc::Status CallRpc(v1::Retime::Stub& stub, const v1::RetimeCurvesRequest& request,
                            v1::RetimeCurvesResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return stub.RetimeCurves(&context, request, response);
}
inline grpc::Status CallRpc(v1::Retime::Stub& stub, const v1::LipBlinkRequest& request,
                            v1::LipBlinkResponse* response) {
  grpc::ClientContext context;
  SetTestDeadline(context);
  return stub.LipBlink(&context, request, response);
}

// Sends `request_bytes` to `method` ("/koma.v1.Retime/RetimeCurves") as they are, through a
// generic stub (nothing parsed or serialised on the client), and returns the call's status;
// the raw bytes of the answer go to `answer` (empty unless OK).
inline grpc::Status RawUnaryCall(InProcessServer& server, const std::string& method,
                                 const std::string& request_bytes, std::string* answer) {
  grpc::GenericStub generic(server.server().InProcessChannel());
  grpc::ClientContext context;
  SetTestDeadline(context);
  grpc::Slice slice(request_bytes);
  const grpc::ByteBuffer request(&slice, 1);
  grpc::ByteBuffer response;
  grpc::Status status;
  grpc::internal::Mutex mu;
  grpc::internal::CondVar cv;
  bool done = false;
  generic.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                    [&](grpc::Status s) {
                      grpc::internal::MutexLock lock(&mu);
                      status = std::move(s);
                      done = true;
                      cv.Signal();
                    });
  {
    grpc::internal::MutexLock lock(&mu);
    while (!done) cv.Wait(&mu);
  }
  answer->clear();
  std::vector<grpc::Slice> slices;
  if (status.ok() && response.Dump(&slices).ok()) {
    for (const grpc::Slice& s : slices) {
      answer->append(reinterpret_cast<const char*>(s.begin()), s.size());
    }
  }
  return status;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_

// koma_api_server: koma.v1.Retime with the production handlers and limits under a chosen
// gRPC server API, to pick the threading model on evidence (issue 5; bench/api_matrix.sh,
// docs/benchmarks.md, "Findings that explain the design"). Benchmark only: loopback,
// plaintext, no health or reflection, no per-call log line except in callback_pool (which
// is koma_server's RetimeService itself).
//   sync             v1::Retime::Service: gRPC's sync thread pool runs the handler.
//   callback_inline  callback API, handler run in the reactor method on gRPC's own callback
//                    threads (gRPC 1.51 on epoll: max(2, cores / 2) of them), no pool.
//   callback_pool    koma_server's RetimeService + WorkerPool (the production model).
//   async            completion queues, one per thread, handler run on the queue thread.
#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/flags/usage.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "bench/api_async.h"
#include "koma/v1/retime.grpc.pb.h"
#include "server/curves_request.h"
#include "server/lip_blink_request.h"
#include "server/logging.h"
#include "server/process_control.h"
#include "server/request_limits.h"
#include "server/retime_service.h"
#include "server/skeletal_request.h"
#include "server/status_mapping.h"
#include "server/worker_pool.h"

ABSL_FLAG(std::string, api, "callback_pool", "sync, callback_inline, callback_pool or async");
ABSL_FLAG(int, worker_threads, 0,
          "threads that run the handlers. callback_pool: the WorkerPool (koma_server's flag; "
          "0 = one per core); async: completion-queue threads (0 = one per core); sync: at "
          "most this many handler threads, calls beyond them get RESOURCE_EXHAUSTED (0 = "
          "gRPC's default, no limit); callback_inline: must be 0 (gRPC's threads)");
ABSL_FLAG(std::string, address, "127.0.0.1:0",
          "host:port to listen on; port 0 picks a free port (see --port_file)");
ABSL_FLAG(std::string, port_file, "",
          "if set, write the bound port number to this file once the server is serving");

namespace {

using koma::server::RequestLimits;
using koma::server::ToGrpcStatus;

constexpr int kMaxMessageBytes = 256 * 1024 * 1024;  // koma_server's default
constexpr int kMaxQueued = 64;                       // koma_server's --max_queued default

// The handler's answer as koma_server gives it: a failed call carries no partial response.
template <typename Response>
grpc::Status Answer(const absl::Status& status, Response* response) {
  if (!status.ok()) response->Clear();
  return ToGrpcStatus(status);
}

class SyncRetime final : public koma::v1::Retime::Service {
 public:
  explicit SyncRetime(const RequestLimits& limits) : limits_(limits) {}

  grpc::Status RetimeSkeletal(grpc::ServerContext*, const koma::v1::RetimeSkeletalRequest* in,
                              koma::v1::RetimeSkeletalResponse* out) override {
    return Answer(koma::server::HandleRetimeSkeletal(*in, limits_, out), out);
  }
  grpc::Status RetimeCurves(grpc::ServerContext*, const koma::v1::RetimeCurvesRequest* in,
                            koma::v1::RetimeCurvesResponse* out) override {
    return Answer(koma::server::HandleRetimeCurves(*in, limits_, out), out);
  }
  grpc::Status LipBlink(grpc::ServerContext*, const koma::v1::LipBlinkRequest* in,
                        koma::v1::LipBlinkResponse* out) override {
    return Answer(koma::server::HandleLipBlink(*in, limits_, out), out);
  }

 private:
  const RequestLimits limits_;
};

// Finishes in the reactor method itself: the handler runs on gRPC's callback thread.
class InlineRetime final : public koma::v1::Retime::CallbackService {
 public:
  explicit InlineRetime(const RequestLimits& limits) : limits_(limits) {}

  grpc::ServerUnaryReactor* RetimeSkeletal(grpc::CallbackServerContext* context,
                                           const koma::v1::RetimeSkeletalRequest* in,
                                           koma::v1::RetimeSkeletalResponse* out) override {
    return Finish(context, Answer(koma::server::HandleRetimeSkeletal(*in, limits_, out), out));
  }
  grpc::ServerUnaryReactor* RetimeCurves(grpc::CallbackServerContext* context,
                                         const koma::v1::RetimeCurvesRequest* in,
                                         koma::v1::RetimeCurvesResponse* out) override {
    return Finish(context, Answer(koma::server::HandleRetimeCurves(*in, limits_, out), out));
  }
  grpc::ServerUnaryReactor* LipBlink(grpc::CallbackServerContext* context,
                                     const koma::v1::LipBlinkRequest* in,
                                     koma::v1::LipBlinkResponse* out) override {
    return Finish(context, Answer(koma::server::HandleLipBlink(*in, limits_, out), out));
  }

 private:
  static grpc::ServerUnaryReactor* Finish(grpc::CallbackServerContext* context,
                                          grpc::Status status) {
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    reactor->Finish(std::move(status));
    return reactor;
  }

  const RequestLimits limits_;
};

// Caps the sync server's threads with a ResourceQuota. gRPC's sync ThreadManager counts its
// pollers as threads, and a poller that takes a call while no other thread polls and the
// quota is spent answers RESOURCE_EXHAUSTED rather than queueing it. `handlers` + 1 leaves
// one poller beside `handlers` busy threads; a thread still finishing its last call does not
// poll yet, so some calls are rejected even at concurrency <= handlers (the matrix shows how
// many). MAX_POLLERS at the cap keeps idle threads instead of exiting and respawning them.
void LimitSyncThreads(grpc::ServerBuilder& builder, int handlers) {
  grpc::ResourceQuota quota("koma_api_server");
  quota.SetMaxThreads(handlers + 1);
  builder.SetResourceQuota(quota);
  builder.SetSyncServerOption(grpc::ServerBuilder::SyncServerOption::NUM_CQS, 1);
  builder.SetSyncServerOption(grpc::ServerBuilder::SyncServerOption::MIN_POLLERS, 1);
  builder.SetSyncServerOption(grpc::ServerBuilder::SyncServerOption::MAX_POLLERS, handlers + 1);
}

// Whichever service --api asked for, owned for the server's lifetime.
struct Services {
  std::unique_ptr<grpc::Service> service;           // sync, callback_inline, callback_pool
  std::unique_ptr<koma::server::WorkerPool> pool;   // callback_pool
  std::unique_ptr<koma::bench::AsyncRetime> async;  // async
};

int ThreadsOrCores(int threads) {
  return threads > 0 ? threads
                     : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Registers the --api service on `builder`; an error names the flag.
absl::Status Register(const std::string& api, int threads, const RequestLimits& limits,
                      grpc::ServerBuilder& builder, Services& out) {
  if (threads < 0) return absl::InvalidArgumentError("--worker_threads: must be >= 0");
  if (api == "sync") {
    out.service = std::make_unique<SyncRetime>(limits);
    if (threads > 0) LimitSyncThreads(builder, threads);
  } else if (api == "callback_inline") {
    if (threads != 0) return absl::InvalidArgumentError("--worker_threads: must be 0 here");
    out.service = std::make_unique<InlineRetime>(limits);
  } else if (api == "callback_pool") {
    out.pool = std::make_unique<koma::server::WorkerPool>(ThreadsOrCores(threads), kMaxQueued);
    out.service = std::make_unique<koma::server::RetimeService>(limits, out.pool.get());
  } else if (api == "async") {
    out.async =
        std::make_unique<koma::bench::AsyncRetime>(builder, limits, ThreadsOrCores(threads));
    return absl::OkStatus();
  } else {
    return absl::InvalidArgumentError(absl::StrCat(
        "--api: \"", api, "\" (expected sync, callback_inline, callback_pool or async)"));
  }
  builder.RegisterService(out.service.get());
  return absl::OkStatus();
}

int Fail(const std::string& message) {
  std::fprintf(stderr, "koma_api_server: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  absl::SetProgramUsageMessage(
      "koma_api_server --api=sync|callback_inline|callback_pool|async [--worker_threads=N] "
      "[--address=HOST:PORT] [--port_file=F]: koma.v1.Retime under one gRPC server API "
      "(benchmark only)");
  absl::ParseCommandLine(argc, argv);
  // RetimeService logs a line per call at info; warn keeps stderr quiet, as koma_server
  // was run for docs/benchmarks.md (the record is still built, as in production).
  if (absl::Status s = koma::server::ConfigureLogging("warn", "text"); !s.ok()) {
    return Fail(std::string(s.message()));
  }
  koma::server::StopSignals stop_signals;  // as koma_server, before gRPC starts any thread

  const std::string api = absl::GetFlag(FLAGS_api);
  const std::string address = absl::GetFlag(FLAGS_address);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(address, grpc::InsecureServerCredentials(), &port);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  Services services;
  if (absl::Status s =
          Register(api, absl::GetFlag(FLAGS_worker_threads), RequestLimits(), builder, services);
      !s.ok()) {
    return Fail(std::string(s.message()));
  }
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (server == nullptr || port == 0) {
    return Fail(absl::StrCat("--address: could not listen on ", address));
  }
  if (services.async) services.async->Start();
  const std::string port_file = absl::GetFlag(FLAGS_port_file);
  if (!port_file.empty() && !koma::server::WritePortFile(port_file, port)) {
    return Fail(absl::StrCat("--port_file: cannot write ", port_file));
  }
  std::fprintf(stderr, "koma_api_server --api=%s listening on port %d\n", api.c_str(), port);

  stop_signals.Wait();
  // Calls in flight get 5 s; the pool (callback_pool) keeps running until then so their
  // reactors are finished, and async's queues are drained only after the server is down.
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(5));
  if (services.async) services.async->Stop();
  services.pool.reset();
  server->Wait();
  server.reset();  // before the services and queues it refers to
  std::fprintf(stderr, "koma_api_server stopped\n");
  return 0;
}

// koma.v1.Retime on gRPC's completion-queue (async) API, for koma_api_server only: N threads,
// each draining its own completion queue, each call a small state machine (requested ->
// answered -> done) that runs the production handler on the thread that dequeued it.
#ifndef KOMA_BENCH_API_ASYNC_H_
#define KOMA_BENCH_API_ASYNC_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <thread>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/request_limits.h"

namespace koma::bench {

class AsyncRetime {
 public:
  // Registers the service and one completion queue per thread on `builder`; call before
  // BuildAndStart, then Start.
  AsyncRetime(grpc::ServerBuilder& builder, const server::RequestLimits& limits, int threads);
  ~AsyncRetime() { Stop(); }

  AsyncRetime(const AsyncRetime&) = delete;
  AsyncRetime& operator=(const AsyncRetime&) = delete;

  // Asks for the first call of each RPC on every queue and starts the threads.
  void Start();
  // Shuts the queues down, drains them and joins the threads; the server must be shut down
  // first, and destroyed only after this (it still refers to the queues). Idempotent.
  void Stop();

 private:
  const server::RequestLimits limits_;
  v1::Retime::AsyncService service_;
  std::vector<std::unique_ptr<grpc::ServerCompletionQueue>> queues_;
  std::vector<std::thread> threads_;
};

}  // namespace koma::bench

#endif  // KOMA_BENCH_API_ASYNC_H_

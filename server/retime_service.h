// The koma.v1.Retime service on gRPC's callback API. Small calls run on gRPC's callback
// thread; large ones are handed to a WorkerPool, so a call of seconds never holds one of
// gRPC's event threads, and the reactor is finished from the worker.
#ifndef KOMA_SERVER_RETIME_SERVICE_H_
#define KOMA_SERVER_RETIME_SERVICE_H_

#include <grpcpp/grpcpp.h>

#include <memory>

#include "koma/v1/retime.grpc.pb.h"
#include "server/idle_trim.h"
#include "server/live_stream.h"
#include "server/logging.h"
#include "server/memory_budget.h"
#include "server/metrics.h"
#include "server/request_limits.h"
#include "server/worker_pool.h"

namespace koma::server {

// All three methods are raw (bytes in, bytes out): the service parses each request itself, so
// RetimeSkeletal's big value array and LipBlink's sample arrays are allocated once at their
// size (server/skeletal_parse.h, ParseRequest in retime_service.cc), each request's size is
// its received length and each response is sized once (ArenaBytesCall in retime_service.cc).
class RetimeService final
    : public v1::Retime::WithRawCallbackMethod_LipBlink<v1::Retime::WithRawCallbackMethod_RetimeCurves<
          v1::Retime::WithRawCallbackMethod_RetimeSkeletal<v1::Retime::CallbackService>>> {
 public:
  // Requests of at most this many serialised bytes run on gRPC's callback thread itself.
  static constexpr int64_t kDefaultInlineMaxBytes = 256 * 1024;

  // `pool` must outlive the service and every call it accepted; so must `metrics` and
  // `trimmer`, which may be null (no metrics, no trimming when idle). Calls whose request is
  // at most `inline_max_bytes` run inline, the rest on `pool` (see Dispatch). With a `budget`
  // (--max_memory_mb; null: none), each call reserves its expected memory first
  // (server/call_footprint.h) and is answered RESOURCE_EXHAUSTED when it does not fit.
  RetimeService(const RequestLimits& limits, WorkerPool* pool, const RpcMetrics* metrics = nullptr,
                int64_t inline_max_bytes = kDefaultInlineMaxBytes, IdleTrimmer* trimmer = nullptr,
                MemoryBudget* budget = nullptr)
      : limits_(limits),
        pool_(pool),
        metrics_(metrics),
        inline_max_bytes_(inline_max_bytes),
        trimmer_(trimmer),
        budget_(budget),
        live_streams_(limits) {}

  grpc::ServerUnaryReactor* RetimeSkeletal(grpc::CallbackServerContext* context,
                                           const grpc::ByteBuffer* request,
                                           grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* RetimeCurves(grpc::CallbackServerContext* context,
                                         const grpc::ByteBuffer* request,
                                         grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* LipBlink(grpc::CallbackServerContext* context,
                                     const grpc::ByteBuffer* request,
                                     grpc::ByteBuffer* response) override;
  // A typed bidirectional stream (server/live_stream.h); the analysis of a message is
  // microseconds, so it runs on gRPC's callback thread.
  grpc::ServerBidiReactor<v1::LiveLipBlinkRequest, v1::LiveLipBlinkFrame>* LiveLipBlink(
      grpc::CallbackServerContext* context) override {
    return live_streams_.Open(context);
  }
  // Shutdown: every live stream ends with UNAVAILABLE after the frames decided so far, and new
  // ones are refused, so a stream does not hold the drain for its whole grace.
  void EndLiveStreams() { live_streams_.EndAll(); }
  int live_streams_in_flight() const { return live_streams_.in_flight(); }

 private:
  // Runs `call` (its Run, FreeRequest, then Answer or DropAnswer; see retime_service.cc):
  // inline when the request is small, else on the worker pool, or answers RESOURCE_EXHAUSTED
  // when the pool's queue is full; logs one line and counts the call in the metrics of
  // `method` when finished.
  template <typename Call>
  grpc::ServerUnaryReactor* Dispatch(grpc::CallbackServerContext* context,
                                     std::shared_ptr<Call> call, RpcMethod method,
                                     RpcRecord record);
  // Dispatch for a raw method: the service parses the bytes into a Request on the call's
  // arena, `handler(request, &answer)` returns absl::Status, and the Answer type serialises
  // itself (ArenaBytesCall in retime_service.cc).
  template <typename Request, typename Answer, typename Handler>
  grpc::ServerUnaryReactor* DispatchRaw(grpc::CallbackServerContext* context,
                                        const grpc::ByteBuffer* request, grpc::ByteBuffer* response,
                                        RpcMethod method, RpcRecord record, Handler handler);

  const RequestLimits limits_;
  WorkerPool* const pool_;
  const RpcMetrics* const metrics_;
  const int64_t inline_max_bytes_;
  IdleTrimmer* const trimmer_;
  MemoryBudget* const budget_;
  LiveStreams live_streams_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_RETIME_SERVICE_H_

#include "server/retime_service.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "core/split_mix64.h"
#include "server/curves_request.h"
#include "server/lip_blink_request.h"
#include "server/logging.h"
#include "server/skeletal_request.h"
#include "server/status_mapping.h"

namespace koma::server {
namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Finishes the call, writes its log line and counts it in `metrics` (null: no metrics).
// `response` is cleared on error so a failed call never carries a partial answer.
template <typename Response>
void FinishAndLog(grpc::ServerUnaryReactor* reactor, grpc::Status status, Response* response,
                  RpcRecord record, Clock::time_point start, const CallMetrics* metrics) {
  if (status.ok()) {
    record.bytes_out = static_cast<int64_t>(response->ByteSizeLong());
  } else {
    response->Clear();
    record.error = status.error_message();
  }
  record.code = status.error_code();
  record.latency_ms = MillisecondsSince(start);
  LogRpc(record);
  if (metrics != nullptr) {
    // record.frames is the request's frame_count; on OK the handler validated it against
    // the data, so it is the number of frames retimed.
    metrics->Finish(record.code, record.latency_ms / 1000.0, record.frames, record.bytes_in,
                    record.bytes_out);
  }
  reactor->Finish(std::move(status));
}

grpc::Status Busy(absl::string_view method) {
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      absl::StrCat(method,
                                   ": server busy, the request queue is full "
                                   "(--max_queued); retry with backoff"));
}

constexpr absl::string_view kRequestIdKey = "x-request-id";
constexpr size_t kMaxRequestIdBytes = 128;

// The caller's x-request-id (cut to 128 bytes), or a new one: 16 hex digits from a
// SplitMix64 stream seeded once from the clock. Returned to the caller in the initial
// metadata and written in the call's log line, so a client log and a server log can be
// joined.
std::string RequestId(const grpc::CallbackServerContext& context) {
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find(std::string(kRequestIdKey));
  if (found != metadata.end() && found->second.size() > 0) {
    return std::string(found->second.data(), std::min(found->second.size(), kMaxRequestIdBytes));
  }
  static std::atomic<uint64_t> counter{
      static_cast<uint64_t>(std::chrono::system_clock::now().time_since_epoch().count())};
  SplitMix64 rng(counter.fetch_add(1));
  return absl::StrFormat("%016x", rng.Next());
}

}  // namespace

template <typename Request, typename Response, typename Handler>
grpc::ServerUnaryReactor* RetimeService::Dispatch(grpc::CallbackServerContext* context,
                                                  const Request* request, Response* response,
                                                  RpcMethod method, RpcRecord record,
                                                  Handler handler) {
  const Clock::time_point start = Clock::now();
  const CallMetrics* metrics = metrics_ != nullptr ? &metrics_->ForMethod(method) : nullptr;
  if (metrics != nullptr) metrics->Start();
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  record.peer = context->peer();
  record.request_id = RequestId(*context);
  context->AddInitialMetadata(std::string(kRequestIdKey), record.request_id);
  record.bytes_in = static_cast<int64_t>(request->ByteSizeLong());
  auto run = [context, request, response, reactor, record, start, metrics, handler]() {
    grpc::Status status;
    if (context->IsCancelled()) {
      status = grpc::Status(grpc::StatusCode::CANCELLED, "cancelled before it started");
    } else {
      status = ToGrpcStatus(handler(*request, response));
    }
    // The handler has read all it needs: drop the request's arena now rather than after
    // the response is sent (a large clip's request is as big as its response).
    context->GetRpcAllocatorState()->FreeRequest();
    FinishAndLog(reactor, std::move(status), response, record, start, metrics);
  };
  // A small call (a Pitch-size clip is ~100 KB and retimes in well under a millisecond) runs
  // right here: handing it to a worker and back costs a thread wake-up each way, which on 2
  // cores measured as much as the retiming (docs/benchmarks.md, "Inline small calls"). Large
  // calls go to the pool, so a call of seconds never holds one of gRPC's few callback threads
  // and the bounded queue still applies to them.
  if (record.bytes_in <= inline_max_bytes_) {
    run();
  } else if (!pool_->TrySubmit(std::move(run))) {
    FinishAndLog(reactor, Busy(record.method), response, record, start, metrics);
  }
  return reactor;
}

grpc::ServerUnaryReactor* RetimeService::RetimeSkeletal(grpc::CallbackServerContext* context,
                                                        const v1::RetimeSkeletalRequest* request,
                                                        v1::RetimeSkeletalResponse* response) {
  RpcRecord record;
  record.method = "RetimeSkeletal";
  record.frames = request->motion().frame_count();
  record.joints = request->motion().skeleton().joints_size();
  return Dispatch(
      context, request, response, RpcMethod::kRetimeSkeletal, std::move(record),
      [this](const auto& in, auto* out) { return HandleRetimeSkeletal(in, limits_, out); });
}

grpc::ServerUnaryReactor* RetimeService::RetimeCurves(grpc::CallbackServerContext* context,
                                                      const v1::RetimeCurvesRequest* request,
                                                      v1::RetimeCurvesResponse* response) {
  RpcRecord record;
  record.method = "RetimeCurves";
  record.frames = request->curves().frame_count();
  record.curves = request->curves().curves_size();
  return Dispatch(
      context, request, response, RpcMethod::kRetimeCurves, std::move(record),
      [this](const auto& in, auto* out) { return HandleRetimeCurves(in, limits_, out); });
}

grpc::ServerUnaryReactor* RetimeService::LipBlink(grpc::CallbackServerContext* context,
                                                  const v1::LipBlinkRequest* request,
                                                  v1::LipBlinkResponse* response) {
  RpcRecord record;
  record.method = "LipBlink";
  record.frames = request->curves().frame_count();
  record.curves = request->curves().curves_size();
  return Dispatch(context, request, response, RpcMethod::kLipBlink, std::move(record),
                  [this](const auto& in, auto* out) { return HandleLipBlink(in, limits_, out); });
}

}  // namespace koma::server

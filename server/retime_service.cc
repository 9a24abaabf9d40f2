#include "server/retime_service.h"

#include <chrono>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/logging.h"
#include "server/skeletal_request.h"
#include "server/status_mapping.h"

namespace koma::server {
namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Finishes the call and writes its log line. `response` is cleared on error so a failed
// call never carries a partial answer.
template <typename Response>
void FinishAndLog(grpc::ServerUnaryReactor* reactor, grpc::Status status, Response* response,
                  RpcRecord record, Clock::time_point start) {
  if (status.ok()) {
    record.bytes_out = static_cast<int64_t>(response->ByteSizeLong());
  } else {
    response->Clear();
    record.error = status.error_message();
  }
  record.code = status.error_code();
  record.latency_ms = MillisecondsSince(start);
  LogRpc(record);
  reactor->Finish(std::move(status));
}

grpc::Status Busy(absl::string_view method) {
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      absl::StrCat(method, ": server busy, the request queue is full "
                                           "(--max_queued); retry with backoff"));
}

// Answers UNIMPLEMENTED for an RPC that is declared in koma.v1 but not built yet.
template <typename Response>
grpc::ServerUnaryReactor* Unimplemented(grpc::CallbackServerContext* context, Response* response,
                                        absl::string_view method, absl::string_view issue) {
  RpcRecord record;
  record.method = method;
  record.peer = context->peer();
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  FinishAndLog(reactor,
               grpc::Status(grpc::StatusCode::UNIMPLEMENTED,
                            absl::StrCat(method, " is not implemented yet (koma.v1, ", issue, ")")),
               response, record, Clock::now());
  return reactor;
}

}  // namespace

grpc::ServerUnaryReactor* RetimeService::RetimeSkeletal(
    grpc::CallbackServerContext* context, const v1::RetimeSkeletalRequest* request,
    v1::RetimeSkeletalResponse* response) {
  const Clock::time_point start = Clock::now();
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  RpcRecord record;
  record.method = "RetimeSkeletal";
  record.peer = context->peer();
  record.frames = request->motion().frame_count();
  record.joints = request->motion().skeleton().joints_size();
  record.bytes_in = static_cast<int64_t>(request->ByteSizeLong());
  const bool accepted = pool_->TrySubmit([this, context, request, response, reactor, record,
                                          start]() {
    grpc::Status status;
    if (context->IsCancelled()) {
      status = grpc::Status(grpc::StatusCode::CANCELLED, "cancelled before it started");
    } else {
      status = ToGrpcStatus(HandleRetimeSkeletal(*request, limits_, response));
    }
    FinishAndLog(reactor, std::move(status), response, record, start);
  });
  if (!accepted) FinishAndLog(reactor, Busy(record.method), response, record, start);
  return reactor;
}

grpc::ServerUnaryReactor* RetimeService::RetimeCurves(grpc::CallbackServerContext* context,
                                                      const v1::RetimeCurvesRequest*,
                                                      v1::RetimeCurvesResponse* response) {
  return Unimplemented(context, response, "RetimeCurves", "issue 3");
}

grpc::ServerUnaryReactor* RetimeService::LipBlink(grpc::CallbackServerContext* context,
                                                  const v1::LipBlinkRequest*,
                                                  v1::LipBlinkResponse* response) {
  return Unimplemented(context, response, "LipBlink", "issue 4");
}

}  // namespace koma::server

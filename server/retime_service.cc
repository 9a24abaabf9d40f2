#include "server/retime_service.h"

#include <grpcpp/support/proto_buffer_reader.h>
#include <grpcpp/support/proto_buffer_writer.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>

#include "absl/strings/str_cat.h"
#include "core/split_mix64.h"
#include "server/arena_allocator.h"
#include "server/call_footprint.h"
#include "server/call_reservation.h"
#include "server/call_stop.h"
#include "server/curves_request.h"
#include "server/curves_response.h"
#include "server/file_requests.h"
#include "server/lip_blink_request.h"
#include "server/logging.h"
#include "server/skeletal_parse.h"
#include "server/skeletal_request.h"
#include "server/status_mapping.h"

namespace koma::server {
namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Finishes the call, writes its log line and counts it in `metrics` (null: no metrics).
// `call.Answer(ok)` turns the outcome into the response to send and returns its size; on error
// it sends nothing, so a failed call never carries a partial answer.
template <typename Call>
void FinishAndLog(grpc::CallbackServerContext* context, grpc::ServerUnaryReactor* reactor,
                  grpc::Status status, Call& call, RpcRecord record, Clock::time_point start,
                  const CallMetrics* metrics) {
  if (status.ok()) {
    absl::StatusOr<int64_t> bytes_out = call.Answer();
    if (bytes_out.ok()) {
      record.bytes_out = *bytes_out;
    } else {
      status = ToGrpcStatus(bytes_out.status());
    }
  }
  if (!status.ok()) {
    call.DropAnswer();
    record.error = status.error_message();
  }
  record.code = status.error_code();
  record.latency_ms = MillisecondsSince(start);
  // The peer's address is a string gRPC builds on request: only for a line that is written
  // (at the default level every call's; at warn, only an INTERNAL error's).
  if (RpcLineLogged(record)) {
    record.peer = context->peer();
    LogRpc(record);
  }
  if (metrics != nullptr) {
    // record.frames is the request's frame_count; on OK the handler validated it against
    // the data, so it is the number of frames retimed.
    metrics->Finish(record.code, record.latency_ms / 1000.0, record.frames, record.bytes_in,
                    record.bytes_out);
  }
  reactor->Finish(std::move(status));
}

// For the raw methods: `response` serialised into the bytes gRPC sends; returns their length.
template <typename Response>
absl::StatusOr<int64_t> SerialiseInto(const Response& response, grpc::ByteBuffer* bytes) {
  bool own_buffer = false;
  const grpc::Status serialised =
      grpc::GenericSerialize<grpc::ProtoBufferWriter, Response>(response, bytes, &own_buffer);
  if (!serialised.ok()) {
    return absl::InternalError(
        absl::StrCat("response: cannot be serialised: ", serialised.error_message()));
  }
  return static_cast<int64_t>(bytes->Length());
}

// RetimeCurves: the wire bytes encoded straight from the core's result, no response messages
// in between (server/curves_response.h). A large response goes out in slices of about
// kCurvesSliceBytes, below the 1 MiB from which malloc maps blocks of their own
// (platform/malloc_tuning.h), so each slice reuses the heap memory of the curves written before
// it, which are freed as they are written.
constexpr size_t kCurvesSliceBytes = 512 * 1024;
absl::StatusOr<int64_t> SerialiseInto(CurvesAnswer& answer, grpc::ByteBuffer* bytes) {
  const CurvesResponseEncoder encoder(answer.set, answer.result);
  const size_t size = encoder.size() + answer.file_field.size();
  if (size > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
    return absl::InternalError(absl::StrCat("response: cannot be serialised: ", size,
                                            " bytes is over protobuf's 2 GiB message limit"));
  }
  // A file request's retimed file: its field (6 or 7) follows the encoder's 1-5 and precedes
  // its 20-21.
  std::vector<grpc::Slice> slices =
      EncodeInSlices(encoder, answer.result, kCurvesSliceBytes, std::move(answer.file_field));
  grpc::ByteBuffer(slices.data(), slices.size()).Swap(bytes);
  return static_cast<int64_t>(size);
}

// RetimeSkeletal: the handler already wrote the bytes (server/skeletal_response.h).
absl::StatusOr<int64_t> SerialiseInto(SkeletalAnswer& answer, grpc::ByteBuffer* bytes) {
  const int64_t size = static_cast<int64_t>(answer.bytes.size());
  grpc::ByteBuffer(&answer.bytes, 1).Swap(bytes);
  answer.bytes = grpc::Slice();
  return size;
}

// The work left once the handler has read the request and it is freed: RetimeCurves' handler
// only validates (PrepareCurvesAnswer), so its parsed request is gone before the retiming
// builds the result. The other answers are complete when their handler returns.
absl::Status CompleteAnswer(CurvesAnswer& answer) { return CompleteCurvesAnswer(&answer); }
template <typename Answer>
absl::Status CompleteAnswer(Answer&) {
  return absl::OkStatus();
}

// The request's frames and joints or curves, for the call's log line and metrics.
void DescribeRequest(const v1::RetimeSkeletalRequest& request, RpcRecord& record) {
  record.frames = request.motion().frame_count();
  record.joints = request.motion().skeleton().joints_size();
}
void DescribeRequest(const v1::RetimeCurvesRequest& request, RpcRecord& record) {
  record.frames = request.curves().frame_count();
  record.curves = request.curves().curves_size();
}
void DescribeRequest(const v1::LipBlinkRequest& request, RpcRecord& record) {
  record.frames = request.curves().frame_count();
  record.curves = request.curves().curves_size();
}
// A request that carried a file (server/file_requests.h) is described once it is parsed:
// from its answer.
void DescribeAnswer(const SkeletalAnswer& answer, RpcRecord& record) {
  record.frames = answer.frames;
  record.joints = answer.joints;
  record.warnings = answer.warnings;
}
void DescribeAnswer(const CurvesAnswer& answer, RpcRecord& record) {
  record.frames = answer.set.frame_count;
  record.curves = static_cast<int>(answer.set.curves.size());
}
// LipBlink's handler describes the motion it converted itself (HandleLipBlink's shape).
void DescribeAnswer(const v1::LipBlinkResponse&, RpcRecord&) {}

// Parses the received bytes into `request` and frees them (they are not read again; the
// buffer belongs to the call, and Clear() leaves it empty, which gRPC's cleanup accepts).
// As gRPC's own parse for a typed method:
template <typename Request>
absl::Status NotA() {
  return absl::InvalidArgumentError(absl::StrCat("request: the bytes are not a valid ",
                                                 Request::descriptor()->full_name(),
                                                 " (protobuf parse failed)"));
}
template <typename Request>
absl::Status ParseRequest(const grpc::ByteBuffer* bytes, Request* request) {
  const grpc::Status parsed = grpc::GenericDeserialize<grpc::ProtoBufferReader, Request>(
      const_cast<grpc::ByteBuffer*>(bytes), request);  // it also Clear()s the bytes
  return parsed.ok() ? absl::OkStatus() : NotA<Request>();
}
// LipBlink: from one contiguous copy of the bytes when they are large. They arrive in many
// slices, and protobuf grows each curve's packed samples slice by slice, doubling them; on the
// arena every outgrown copy stays until the call ends (3 curves x 100k frames: 5.6 MB of
// sample arrays for 2.4 MB of samples, measured with massif). From one buffer each array is
// reserved once at its size; the copy is freed as soon as the parse is done.
absl::Status ParseRequest(const grpc::ByteBuffer* bytes, v1::LipBlinkRequest* request) {
  constexpr size_t kContiguousFromBytes = 1 << 20;
  if (bytes->Length() < kContiguousFromBytes) {
    return ParseRequest<v1::LipBlinkRequest>(bytes, request);
  }
  grpc::Slice contiguous;
  const bool copied = bytes->DumpToSingleSlice(&contiguous).ok();
  const_cast<grpc::ByteBuffer*>(bytes)->Clear();
  const bool parsed =
      copied && request->ParseFromArray(contiguous.begin(), static_cast<int>(contiguous.size()));
  return parsed ? absl::OkStatus() : NotA<v1::LipBlinkRequest>();
}

// RetimeSkeletal: the big value array reserved once at its size (server/skeletal_parse.h).
absl::Status ParseRequest(const grpc::ByteBuffer* bytes, v1::RetimeSkeletalRequest* request) {
  const absl::Status parsed = ParseSkeletalRequest(*bytes, request);
  const_cast<grpc::ByteBuffer*>(bytes)->Clear();
  return parsed;
}

// Where a raw call's answer waits to be serialised: a message on the call's own response
// arena, or an answer type with its own SerialiseInto (CurvesAnswer, SkeletalAnswer), held as
// it is.
template <typename Response, bool = std::is_base_of_v<google::protobuf::MessageLite, Response>>
class AnswerSlot {
 public:
  AnswerSlot()
      : arena_(CallArenaOptions()),
        message_(google::protobuf::Arena::CreateMessage<Response>(&arena_)) {}
  Response* get() { return message_; }

 private:
  google::protobuf::Arena arena_;
  Response* message_;
};
template <typename Response>
class AnswerSlot<Response, false> {
 public:
  Response* get() { return &answer_; }

 private:
  Response answer_;
};

// A call on a raw method whose request and response are ordinary messages on per-call arenas
// (as the typed API with server/arena_allocator.h), parsed and serialised by the service
// itself. The point is the sizes: the typed API gives the handler no received bytes, so the
// call's log line and metrics took the request's size from ByteSizeLong (a walk over every
// submessage), and the response's size was computed twice, once for the log before Finish and
// again by gRPC when it serialised. Here the request's size is the received length and the
// response is serialised before Finish with one ByteSizeLong: on RetimeCurves 60 x 300 (~8,000
// submessages each way) the two walks were ~10 % of the server's CPU. For RetimeSkeletal and
// LipBlink the parse also allocates the big arrays once at their size (ParseRequest above).
// LipBlink's answer is a message; the other two are not messages at all. RetimeCurves' handler
// only validates: the retiming runs once the request is freed (CompleteAnswer), and the bytes
// are encoded from the core's result after that (SerialiseInto(CurvesAnswer) above).
// RetimeSkeletal's bytes are written by the handler itself, while the request whose frames it
// copies is still alive (server/skeletal_response.h).
template <typename Request, typename Response, typename Handler>
class ArenaBytesCall {
 public:
  ArenaBytesCall(const grpc::ByteBuffer* request_bytes, grpc::ByteBuffer* response_bytes,
                 const RequestLimits& limits, Handler handler)
      : request_bytes_(request_bytes),
        response_bytes_(response_bytes),
        limits_(limits),
        handler_(std::move(handler)),
        request_arena_(std::make_unique<google::protobuf::Arena>(CallArenaOptions())),
        request_(google::protobuf::Arena::CreateMessage<Request>(request_arena_.get())) {}

  int64_t BytesIn() const { return static_cast<int64_t>(request_bytes_->Length()); }
  // The memory budget's reservation for the received bytes (Dispatch), held until the call
  // object goes and grown to the call's expected footprint once the request is parsed.
  void Hold(MemoryBudget::Reservation reservation) { reservation_ = std::move(reservation); }

  grpc::Status Run(RpcRecord& record) {
    const int64_t bytes_in = BytesIn();
    const absl::Status parsed = ParseRequest(request_bytes_, request_);
    if (!parsed.ok()) return ToGrpcStatus(parsed);
    DescribeRequest(*request_, record);
    if (reservation_.budgeted()) {
      const absl::Status fits = reservation_.Resize(ExpectedFootprint(*request_, bytes_in, limits_),
                                                    "this call (request, work, response)");
      if (!fits.ok()) return ToGrpcStatus(fits);
    }
    absl::Status handled;
    {
      // A file request grows its reservation once its file is parsed (server/file_requests.h).
      const CallReservationScope scope(&reservation_);
      handled = handler_(*request_, response_.get(), record);
    }
    if (handled.ok() && CarriesFile(*request_)) DescribeAnswer(*response_.get(), record);
    FreeRequest();
    if (handled.ok()) handled = CompleteAnswer(*response_.get());
    return ToGrpcStatus(handled);
  }
  // The handler has read all it needs: drop the request's arena now rather than after the
  // response is sent. Run calls it once the handler returns; Dispatch calls it again after
  // Run, for the calls whose parse failed, and a second call does nothing.
  void FreeRequest() {
    request_ = nullptr;
    request_arena_.reset();
  }
  absl::StatusOr<int64_t> Answer() { return SerialiseInto(*response_.get(), response_bytes_); }
  void DropAnswer() { response_bytes_->Clear(); }

 private:
  const grpc::ByteBuffer* request_bytes_;
  grpc::ByteBuffer* response_bytes_;
  const RequestLimits& limits_;
  Handler handler_;
  MemoryBudget::Reservation reservation_;
  std::unique_ptr<google::protobuf::Arena> request_arena_;
  Request* request_;
  AnswerSlot<Response> response_;
};

// Why the pool refused a call.
grpc::Status Refused(absl::string_view method, WorkerPool::Submission submission) {
  if (submission == WorkerPool::Submission::kStopping) {
    return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                        absl::StrCat(method, ": the server is shutting down"));
  }
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      absl::StrCat(method,
                                   ": server busy, the request queue is full "
                                   "(--max_queued); retry with backoff"));
}

}  // namespace

template <typename Call>
grpc::ServerUnaryReactor* RetimeService::Dispatch(grpc::CallbackServerContext* context,
                                                  std::shared_ptr<Call> call, RpcMethod method,
                                                  RpcRecord record) {
  const Clock::time_point start = Clock::now();
  const CallMetrics* metrics = metrics_ != nullptr ? &metrics_->ForMethod(method) : nullptr;
  if (metrics != nullptr) metrics->Start();
  grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
  record.request_id = TakeRequestId(context);
  record.bytes_in = call->BytesIn();
  if (budget_ != nullptr) {
    absl::StatusOr<MemoryBudget::Reservation> reserved =
        budget_->Reserve(ReceivedFootprint(record.bytes_in), "the received request");
    if (!reserved.ok()) {
      FinishAndLog(context, reactor, ToGrpcStatus(reserved.status()), *call, record, start,
                   metrics);
      return reactor;
    }
    call->Hold(*std::move(reserved));
  }
  IdleTrimmer* const trimmer = trimmer_;
  if (trimmer != nullptr) trimmer->CallStarted(record.bytes_in);
  const double max_call_seconds = limits_.max_call_seconds;
  auto run = [context, call, reactor, record, start, metrics, trimmer, max_call_seconds]() mutable {
    grpc::Status status;
    if (context->IsCancelled()) {
      status = grpc::Status(grpc::StatusCode::CANCELLED, "cancelled before it started");
    } else {
      // The handler's loops poll `stop` (core/stop_check.h); a call it stopped is answered
      // with why, whatever the handler returned.
      const CallStopSignal stop(context, start, max_call_seconds);
      const StopSignalScope scope(&stop);
      status = call->Run(record);
      if (const absl::Status why = stop.Reason(); !why.ok()) status = ToGrpcStatus(why);
    }
    call->FreeRequest();
    FinishAndLog(context, reactor, std::move(status), *call, record, start, metrics);
    if (trimmer != nullptr) trimmer->CallFinished();
  };
  // A small call (a Pitch-size clip is ~100 KB and retimes in well under a millisecond) runs
  // right here: handing it to a worker and back costs a thread wake-up each way, which on 2
  // cores measured as much as the retiming (docs/benchmarks.md, "Findings"). Large
  // calls go to the pool, so a call of seconds never holds one of gRPC's few callback threads
  // and the bounded queue still applies to them.
  if (record.bytes_in <= inline_max_bytes_) {
    run();
  } else if (const WorkerPool::Submission submission = pool_->TrySubmit(run);
             submission != WorkerPool::Submission::kAccepted) {
    FinishAndLog(context, reactor, Refused(record.method, submission), *call, record, start,
                 metrics);
    if (trimmer != nullptr) trimmer->CallFinished();
  }
  return reactor;
}

template <typename Request, typename Answer, typename Handler>
grpc::ServerUnaryReactor* RetimeService::DispatchRaw(grpc::CallbackServerContext* context,
                                                     const grpc::ByteBuffer* request,
                                                     grpc::ByteBuffer* response, RpcMethod method,
                                                     RpcRecord record, Handler handler) {
  return Dispatch(context,
                  std::make_shared<ArenaBytesCall<Request, Answer, Handler>>(
                      request, response, limits_, std::move(handler)),
                  method, std::move(record));
}

grpc::ServerUnaryReactor* RetimeService::RetimeSkeletal(grpc::CallbackServerContext* context,
                                                        const grpc::ByteBuffer* request,
                                                        grpc::ByteBuffer* response) {
  RpcRecord record;
  record.method = "RetimeSkeletal";  // frames and joints are filled in once it is parsed
  return DispatchRaw<v1::RetimeSkeletalRequest, SkeletalAnswer>(
      context, request, response, RpcMethod::kRetimeSkeletal, std::move(record),
      [this](const v1::RetimeSkeletalRequest& in, SkeletalAnswer* out, RpcRecord&) {
        return RetimeSkeletalAnswer(in, limits_, out);
      });
}

grpc::ServerUnaryReactor* RetimeService::RetimeCurves(grpc::CallbackServerContext* context,
                                                      const grpc::ByteBuffer* request,
                                                      grpc::ByteBuffer* response) {
  RpcRecord record;
  record.method = "RetimeCurves";  // frames and curves are filled in once it is parsed
  return DispatchRaw<v1::RetimeCurvesRequest, CurvesAnswer>(
      context, request, response, RpcMethod::kRetimeCurves, std::move(record),
      [this](const v1::RetimeCurvesRequest& in, CurvesAnswer* out, RpcRecord&) {
        return PrepareCurvesAnswer(in, limits_, out);
      });
}

grpc::ServerUnaryReactor* RetimeService::LipBlink(grpc::CallbackServerContext* context,
                                                  const grpc::ByteBuffer* request,
                                                  grpc::ByteBuffer* response) {
  RpcRecord record;
  record.method = "LipBlink";  // frames and curves are filled in once it is parsed
  return DispatchRaw<v1::LipBlinkRequest, v1::LipBlinkResponse>(
      context, request, response, RpcMethod::kLipBlink, std::move(record),
      [this](const v1::LipBlinkRequest& in, v1::LipBlinkResponse* out, RpcRecord& described) {
        LipBlinkMotionShape shape;
        const absl::Status handled = HandleLipBlink(in, limits_, out, &shape);
        if (handled.ok()) {  // else the request's own curves (DescribeRequest) stay
          described.frames = shape.frames;
          described.curves = shape.curves;
        }
        return handled;
      });
}

}  // namespace koma::server

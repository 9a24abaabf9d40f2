#include "bench/api_async.h"

#include <utility>

#include "absl/status/status.h"
#include "server/curves_request.h"
#include "server/lip_blink_request.h"
#include "server/skeletal_request.h"
#include "server/status_mapping.h"

namespace koma::bench {
namespace {

// What every completion-queue tag is: the queue thread calls Proceed with the event's `ok`.
class Tag {
 public:
  virtual ~Tag() = default;
  virtual void Proceed(bool ok) = 0;
};

// One unary call of one RPC. Created already waiting for a call (RequestX); when one
// arrives it first asks for the next (so the queue keeps accepting), runs the handler inline
// and Finishes; the Finish event deletes it. `ok` false means the server is shutting down.
template <typename Request, typename Response>
class UnaryCall final : public Tag {
 public:
  using Service = v1::Retime::AsyncService;
  using RequestMethod = void (Service::*)(grpc::ServerContext*, Request*,
                                          grpc::ServerAsyncResponseWriter<Response>*,
                                          grpc::CompletionQueue*, grpc::ServerCompletionQueue*,
                                          void*);
  using Handler = absl::Status (*)(const Request&, const server::RequestLimits&, Response*);
  struct Method {
    Service* service;
    RequestMethod request;
    Handler handler;
    const server::RequestLimits* limits;
  };

  static void Await(const Method& method, grpc::ServerCompletionQueue* queue) {
    new UnaryCall(method, queue);
  }

  void Proceed(bool ok) override {
    if (answered_ || !ok) {
      delete this;
      return;
    }
    Await(method_, queue_);
    grpc::Status status =
        server::ToGrpcStatus(method_.handler(request_, *method_.limits, &response_));
    answered_ = true;
    if (status.ok()) {
      writer_.Finish(response_, status, this);
    } else {
      writer_.FinishWithError(status, this);  // a failed call never carries a partial answer
    }
  }

 private:
  UnaryCall(const Method& method, grpc::ServerCompletionQueue* queue)
      : method_(method), queue_(queue), writer_(&context_) {
    (method_.service->*method_.request)(&context_, &request_, &writer_, queue_, queue_, this);
  }

  const Method method_;
  grpc::ServerCompletionQueue* const queue_;
  grpc::ServerContext context_;
  Request request_;
  Response response_;
  grpc::ServerAsyncResponseWriter<Response> writer_;
  bool answered_ = false;
};

using SkeletalCall = UnaryCall<v1::RetimeSkeletalRequest, v1::RetimeSkeletalResponse>;
using CurvesCall = UnaryCall<v1::RetimeCurvesRequest, v1::RetimeCurvesResponse>;
using LipBlinkCall = UnaryCall<v1::LipBlinkRequest, v1::LipBlinkResponse>;

}  // namespace

AsyncRetime::AsyncRetime(grpc::ServerBuilder& builder, const server::RequestLimits& limits,
                         int threads)
    : limits_(limits) {
  builder.RegisterService(&service_);
  for (int i = 0; i < threads; ++i) queues_.push_back(builder.AddCompletionQueue());
}

void AsyncRetime::Start() {
  for (const auto& queue : queues_) {
    SkeletalCall::Await({&service_, &v1::Retime::AsyncService::RequestRetimeSkeletal,
                         &server::HandleRetimeSkeletal, &limits_},
                        queue.get());
    CurvesCall::Await({&service_, &v1::Retime::AsyncService::RequestRetimeCurves,
                       &server::HandleRetimeCurves, &limits_},
                      queue.get());
    // HandleLipBlink without the log line's shape (a captureless lambda is a Handler).
    LipBlinkCall::Await({&service_, &v1::Retime::AsyncService::RequestLipBlink,
                         [](const v1::LipBlinkRequest& request,
                            const server::RequestLimits& limits, v1::LipBlinkResponse* response) {
                           return server::HandleLipBlink(request, limits, response);
                         },
                         &limits_},
                        queue.get());
    threads_.emplace_back([queue = queue.get()] {
      void* tag = nullptr;
      bool ok = false;
      while (queue->Next(&tag, &ok)) static_cast<Tag*>(tag)->Proceed(ok);
    });
  }
}

void AsyncRetime::Stop() {
  if (threads_.empty()) return;
  // Next returns false once a shut-down queue is drained; every pending tag is deleted on
  // the way (ok == false).
  for (const auto& queue : queues_) queue->Shutdown();
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
}

}  // namespace koma::bench

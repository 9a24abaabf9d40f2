#include "server/metrics.h"

#include <string>

#include "koma/version.h"
#include "server/status_mapping.h"

namespace koma::server {
namespace {

constexpr char kServiceName[] = "koma.v1.Retime";
constexpr char kUnary[] = "unary";  // every koma RPC is unary

prometheus::Labels GrpcLabels(const char* method) {
  return {{"grpc_type", kUnary}, {"grpc_service", kServiceName}, {"grpc_method", method}};
}

}  // namespace

const char* RpcMethodName(RpcMethod method) {
  switch (method) {
    case RpcMethod::kRetimeSkeletal:
      return "RetimeSkeletal";
    case RpcMethod::kRetimeCurves:
      return "RetimeCurves";
    case RpcMethod::kLipBlink:
      return "LipBlink";
  }
  return "unknown";
}

void CallMetrics::Start() const {
  started_->Increment();
  in_flight_->Increment();
}

void CallMetrics::Finish(grpc::StatusCode code, double seconds, int64_t frames, int64_t bytes_in,
                         int64_t bytes_out) const {
  in_flight_->Decrement();
  const int index = static_cast<int>(code);
  // gRPC never produces a code outside 0..16; count one as UNKNOWN rather than index past.
  const bool known = index >= 0 && index < kGrpcCodeCount;
  handled_[known ? index : static_cast<int>(grpc::StatusCode::UNKNOWN)]->Increment();
  handling_seconds_->Observe(seconds);
  request_bytes_->Increment(static_cast<double>(bytes_in));
  if (code == grpc::StatusCode::OK) {
    frames_->Increment(static_cast<double>(frames));
    response_bytes_->Increment(static_cast<double>(bytes_out));
  }
}

RpcMetrics::RpcMetrics(prometheus::Registry& registry) {
  auto& started = prometheus::BuildCounter()
                      .Name("grpc_server_started_total")
                      .Help("Total number of RPCs started on the server.")
                      .Register(registry);
  auto& handled = prometheus::BuildCounter()
                      .Name("grpc_server_handled_total")
                      .Help(
                          "Total number of RPCs completed on the server, regardless of "
                          "success or failure.")
                      .Register(registry);
  auto& handling = prometheus::BuildHistogram()
                       .Name("grpc_server_handling_seconds")
                       .Help(
                           "Histogram of response latency (seconds) of gRPC that had been "
                           "application-level handled by the server.")
                       .Register(registry);
  auto& frames = prometheus::BuildCounter()
                     .Name("koma_frames_processed_total")
                     .Help("Input frames of the requests that were retimed successfully.")
                     .Register(registry);
  auto& request_bytes = prometheus::BuildCounter()
                            .Name("koma_request_bytes_total")
                            .Help("Serialized request bytes received, every call.")
                            .Register(registry);
  auto& response_bytes = prometheus::BuildCounter()
                             .Name("koma_response_bytes_total")
                             .Help("Serialized response bytes sent by the calls that ended OK.")
                             .Register(registry);
  // koma_build_info{version="0.1.0"} 1: which build answers (the CMake project version).
  prometheus::BuildGauge()
      .Name("koma_build_info")
      .Help("Always 1; the label version is koma's version (koma_server --version).")
      .Register(registry)
      .Add({{"version", kVersion}})
      .Set(1);
  prometheus::Gauge& in_flight = prometheus::BuildGauge()
                                     .Name("koma_requests_in_flight")
                                     .Help(
                                         "RPCs started and not yet finished (queued or "
                                         "running).")
                                     .Register(registry)
                                     .Add({});
  const prometheus::Histogram::BucketBoundaries buckets(kHandlingSecondsBuckets.begin(),
                                                        kHandlingSecondsBuckets.end());
  for (int m = 0; m < kRpcMethodCount; ++m) {
    const char* name = RpcMethodName(static_cast<RpcMethod>(m));
    const prometheus::Labels labels = GrpcLabels(name);
    CallMetrics& call = methods_[m];
    call.started_ = &started.Add(labels);
    for (int code = 0; code < kGrpcCodeCount; ++code) {
      prometheus::Labels with_code = labels;
      with_code["grpc_code"] = GrpcCodeName(static_cast<grpc::StatusCode>(code));
      call.handled_[code] = &handled.Add(with_code);
    }
    call.handling_seconds_ = &handling.Add(labels, buckets);
    call.frames_ = &frames.Add({{"grpc_method", name}});
    call.request_bytes_ = &request_bytes.Add({{"grpc_method", name}});
    call.response_bytes_ = &response_bytes.Add({{"grpc_method", name}});
    call.in_flight_ = &in_flight;
  }
}

}  // namespace koma::server

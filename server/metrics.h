// Prometheus metrics of the koma.v1.Retime RPCs, named as go-grpc-prometheus names them so
// the usual dashboards and alerts work unchanged:
//   grpc_server_started_total{grpc_type, grpc_service, grpc_method}          counter
//   grpc_server_handled_total{grpc_type, grpc_service, grpc_method, grpc_code} counter
//   grpc_server_handling_seconds{grpc_type, grpc_service, grpc_method}        histogram
// and koma's own:
//   koma_frames_processed_total{grpc_method}  input frames of the calls that ended OK
//   koma_request_bytes_total{grpc_method}     serialized request bytes, every call
//   koma_response_bytes_total{grpc_method}    serialized response bytes, calls that ended OK
//   koma_requests_in_flight                   calls started and not yet finished (gauge)
// Bytes are counters, not histograms: rate(bytes) / rate(calls) gives the mean size at a
// fraction of a histogram's cost, and sizes are already in the per-call log line.
//
// Every series (3 methods x 17 codes for handled_total) is created once in the constructor,
// so a call costs a few atomic adds and one uncontended histogram mutex: no Family::Add
// (a mutex and a map lookup) and no string work on the hot path.
#ifndef KOMA_SERVER_METRICS_H_
#define KOMA_SERVER_METRICS_H_

#include <grpcpp/support/status.h>
#include <prometheus/counter.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>

#include <array>
#include <cstdint>

namespace koma::server {

enum class RpcMethod { kRetimeSkeletal, kRetimeCurves, kLipBlink };
inline constexpr int kRpcMethodCount = 3;
// The canonical gRPC codes, OK (0) .. UNAUTHENTICATED (16).
inline constexpr int kGrpcCodeCount = 17;

// "RetimeSkeletal", ...: the grpc_method label.
const char* RpcMethodName(RpcMethod method);

// Upper bounds of grpc_server_handling_seconds, seconds. go-grpc-prometheus uses Prometheus'
// DefBuckets (5 ms .. 10 s); koma answers a small clip in well under 1 ms and a 100k-frame
// clip in seconds, with a 60 s client deadline, so the range is 0.5 ms .. 30 s.
inline constexpr std::array<double, 15> kHandlingSecondsBuckets = {
    0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30};

// The series of one method, all owned by the registry.
class CallMetrics {
 public:
  // A call was accepted by the service (before it is queued).
  void Start() const;
  // The call finished with `code` after `seconds`; `frames` and `bytes_out` count only when
  // `code` is OK (a failed call processed nothing and sends no body).
  void Finish(grpc::StatusCode code, double seconds, int64_t frames, int64_t bytes_in,
              int64_t bytes_out) const;

 private:
  friend class RpcMetrics;

  prometheus::Counter* started_ = nullptr;
  std::array<prometheus::Counter*, kGrpcCodeCount> handled_{};
  prometheus::Histogram* handling_seconds_ = nullptr;
  prometheus::Counter* frames_ = nullptr;
  prometheus::Counter* request_bytes_ = nullptr;
  prometheus::Counter* response_bytes_ = nullptr;
  prometheus::Gauge* in_flight_ = nullptr;  // shared by every method
};

class RpcMetrics {
 public:
  // Registers the families above in `registry`, which must outlive this object, and creates
  // every series at 0 (so a scrape shows them before the first call, and rate() works).
  explicit RpcMetrics(prometheus::Registry& registry);

  RpcMetrics(const RpcMetrics&) = delete;
  RpcMetrics& operator=(const RpcMetrics&) = delete;

  const CallMetrics& ForMethod(RpcMethod method) const {
    return methods_[static_cast<int>(method)];
  }

 private:
  std::array<CallMetrics, kRpcMethodCount> methods_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_METRICS_H_

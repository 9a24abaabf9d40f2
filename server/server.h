// Builds and runs the koma gRPC server: the Retime service, health (grpc.health.v1) and
// reflection (grpc.reflection.v1alpha), with message-size and request limits, and optionally
// Prometheus metrics of the Retime calls on their own HTTP port.
#ifndef KOMA_SERVER_SERVER_H_
#define KOMA_SERVER_SERVER_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "server/http_server.h"
#include "server/idle_trim.h"
#include "server/memory_budget.h"
#include "server/metrics.h"
#include "server/metrics_endpoint.h"
#include "server/request_limits.h"
#include "server/retime_service.h"
#include "server/worker_pool.h"

namespace koma::server {

struct ServerConfig {
  // "127.0.0.1:50051", "[::1]:0" (0 picks a free port), "0.0.0.0:50051" in a container.
  // Empty: no listening port, only InProcessChannel() (tests).
  std::string address = "127.0.0.1:50051";
  // Largest request and response, bytes. 256 MiB holds a 100k-frame, 96-channel clip
  // (77 MB of doubles) in and out with room to spare.
  int max_message_bytes = 256 * 1024 * 1024;
  RequestLimits limits;
  // Threads that run retiming; 0 = one per core.
  int worker_threads = 0;
  // Requests that may wait for a worker before new ones get RESOURCE_EXHAUSTED.
  int max_queued = 64;
  // Requests of at most this many bytes run on gRPC's callback thread, not the pool.
  int64_t inline_max_bytes = RetimeService::kDefaultInlineMaxBytes;
  // Once no call has run for this long, and at least idle_trim_min_request_bytes of requests
  // arrived since the last time, the memory large calls left in malloc's heap goes back to
  // the system (server/idle_trim.h). Zero: never.
  absl::Duration idle_trim = absl::Seconds(1);
  int64_t idle_trim_min_request_bytes = 16 << 20;
  // TLS, as PEM text: both empty = plaintext. With a client CA, clients must present a
  // certificate that CA signed (mutual TLS).
  std::string tls_cert_pem;
  std::string tls_key_pem;
  std::string tls_client_ca_pem;
  // The memory all calls in flight may hold together, MiB (--max_memory_mb; 0 = no budget).
  // A quarter of it bounds what gRPC holds (its ResourceQuota: receive buffers, messages being
  // assembled), half is what koma's calls may reserve (server/memory_budget.h), and the last
  // quarter is headroom for what neither counts: the process' code and threads, malloc's
  // slack, and gRPC's overshoot (its quota slows and refuses streams, it does not stop a
  // message already being received). Measured: 64 x 50 MB requests under 512 MiB peaked at
  // 295-461 MiB (tests/e2e/memory_budget_test.sh), against 3.0-3.2 GiB with no budget.
  int64_t max_memory_mb = 0;
  // Prometheus: "HOST:PORT" serves GET /metrics over plain HTTP there (port 0 picks a free
  // one); empty = no endpoint.
  std::string metrics_address;
  // Where the Retime calls are counted. Null: a new registry when metrics_address is set,
  // else no metrics at all (no per-call cost). Tests pass one to read it in process.
  std::shared_ptr<prometheus::Registry> metrics_registry;
  // The HTTP port (--http_port and the other --http_* flags; server/http_server.h): the
  // Connect JSON API (server/connect_api.h) and the page. port -1 (the default): none.
  HttpServerConfig http;
};

// InvalidArgument naming the first setting out of range (as its koma_server flag) and its
// value; KomaServer::Start checks this first.
absl::Status ValidateServerConfig(const ServerConfig& config);

class KomaServer {
 public:
  static absl::StatusOr<std::unique_ptr<KomaServer>> Start(const ServerConfig& config);
  ~KomaServer();

  // The bound port (the chosen one when the address asked for port 0); 0 without a port.
  int port() const { return port_; }
  // How many times the memory of large calls was given back while idle (server/idle_trim.h).
  int64_t idle_trims() const { return trimmer_->trims(); }
  // The calls' share of --max_memory_mb; null without a budget.
  const MemoryBudget* memory_budget() const { return budget_.get(); }
  // The bound metrics port; 0 without a metrics endpoint.
  int metrics_port() const { return metrics_endpoint_ ? metrics_endpoint_->port() : 0; }
  // LiveLipBlink streams in flight (server/live_stream.h); refused ones are not counted.
  int live_streams_in_flight() const { return service_->live_streams_in_flight(); }
  // The bound HTTP port; 0 without one.
  int http_port() const { return http_ != nullptr ? http_->port() : 0; }
  // The HTTP server, to register more routes on (HttpServer::Handle); null without one.
  HttpServer* http_server() { return http_.get(); }
  // A channel to this server that bypasses the network (tests), with the same size limits.
  std::shared_ptr<grpc::Channel> InProcessChannel();
  // Health to NOT_SERVING ("" and "koma.v1.Retime") while calls are still accepted, so
  // clients and load balancers that watch health stop sending new ones.
  void StopServing();
  // StopServing, stop accepting, let calls in flight finish for up to `grace` then cancel
  // them, and wait for the workers. Safe to call more than once.
  void Shutdown(absl::Duration grace);

 private:
  KomaServer() = default;
  // The registry, the RpcMetrics and the HTTP endpoint that `config` asks for.
  absl::Status StartMetrics(const ServerConfig& config);
  // The HTTP port with the Connect API, when config.http.port is not -1.
  absl::Status StartHttp(const ServerConfig& config);

  int port_ = 0;
  int max_message_bytes_ = 0;
  bool shut_down_ = false;
  // Declaration order is destruction order in reverse: the server goes before the service
  // and the pool it calls into, and those before the metrics they count into.
  std::shared_ptr<prometheus::Registry> metrics_registry_;
  std::unique_ptr<RpcMetrics> metrics_;
  std::unique_ptr<MetricsEndpoint> metrics_endpoint_;
  std::unique_ptr<IdleTrimmer> trimmer_;
  std::unique_ptr<MemoryBudget> budget_;
  std::unique_ptr<WorkerPool> pool_;
  std::unique_ptr<RetimeService> service_;
  std::unique_ptr<grpc::Server> server_;
  // Its handlers call into server_ through the in-process channel: it goes first.
  std::unique_ptr<HttpServer> http_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_SERVER_H_

#include "server/server.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/resource_quota.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "absl/strings/str_cat.h"
#include "server/connect_api.h"
#include "server/logging.h"

namespace koma::server {
namespace {

constexpr char kServiceName[] = "koma.v1.Retime";

int DefaultWorkerThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

std::shared_ptr<grpc::ServerCredentials> Credentials(const ServerConfig& config) {
  if (config.tls_cert_pem.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions options(
      config.tls_client_ca_pem.empty()
          ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
          : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  options.pem_root_certs = config.tls_client_ca_pem;
  options.pem_key_cert_pairs.push_back({config.tls_key_pem, config.tls_cert_pem});
  return grpc::SslServerCredentials(options);
}

}  // namespace

absl::Status ValidateServerConfig(const ServerConfig& config) {
  // Each message names the flag (koma_server's flags map one to one onto these fields) and
  // the value, so a bad deployment fails at start, not at the first call.
  const auto invalid = [](auto&&... parts) {
    return absl::InvalidArgumentError(absl::StrCat(parts...));
  };
  if (config.max_message_bytes < 1024) {
    return invalid("--max_message_bytes: ", config.max_message_bytes, " is below 1024");
  }
  if (config.limits.max_values < 1) {
    return invalid("--max_values: ", config.limits.max_values,
                   " must be >= 1 (it would refuse every request)");
  }
  if (config.limits.max_joints < 1) {
    return invalid("--max_joints: ", config.limits.max_joints,
                   " must be >= 1 (it would refuse every skeleton)");
  }
  if (config.limits.max_file_bytes < 0) {
    return invalid("--max_file_bytes: ", config.limits.max_file_bytes,
                   " must be >= 0 (0 refuses every file-carrying request)");
  }
  if (!(config.limits.max_audio_seconds > 0 && config.limits.max_audio_seconds <= 1e6)) {
    return invalid("--max_audio_seconds: ", config.limits.max_audio_seconds,
                   " must be in (0, 1000000]");
  }
  if (config.limits.max_audio_channels < 1) {
    return invalid("--max_audio_channels: ", config.limits.max_audio_channels, " must be >= 1");
  }
  if (config.limits.max_audio_samples < 1) {
    return invalid("--max_audio_samples: ", config.limits.max_audio_samples,
                   " must be >= 1 (it would refuse every recording)");
  }
  if (config.limits.max_gltf_animations < 1) {
    return invalid("--max_gltf_animations: ", config.limits.max_gltf_animations,
                   " must be >= 1 (it would refuse every glTF file)");
  }
  if (!(config.limits.max_call_seconds >= 0 && config.limits.max_call_seconds <= 1e6)) {
    return invalid("--max_call_seconds: ", config.limits.max_call_seconds,
                   " must be in [0, 1000000] (0: no bound)");
  }
  if (config.limits.live_max_streams < 0) {
    return invalid("--live_max_streams: ", config.limits.live_max_streams,
                   " must be >= 0 (0 refuses every live stream)");
  }
  if (!(config.limits.live_max_seconds > 0 && config.limits.live_max_seconds <= 1e7)) {
    return invalid("--live_max_seconds: ", config.limits.live_max_seconds,
                   " must be in (0, 10000000]");
  }
  if (config.limits.live_max_message_bytes < 64) {
    return invalid("--live_max_message_bytes: ", config.limits.live_max_message_bytes,
                   " must be >= 64");
  }
  if (config.limits.live_max_queued_frames < 1) {
    return invalid("--live_max_queued_frames: ", config.limits.live_max_queued_frames,
                   " must be >= 1");
  }
  if (!(config.limits.live_idle_seconds >= 0 && config.limits.live_idle_seconds <= 1e6)) {
    return invalid("--live_idle_seconds: ", config.limits.live_idle_seconds,
                   " must be in [0, 1000000] (0: no bound)");
  }
  if (config.limits.max_gltf_nodes < 1) {
    return invalid("--max_gltf_nodes: ", config.limits.max_gltf_nodes,
                   " must be >= 1 (it would refuse every glTF file)");
  }
  if (config.limits.threads_per_call < 1) {
    // Not reachable from the flag: koma_server turns --threads_per_call=0 into one per core.
    return invalid("limits.threads_per_call: ", config.limits.threads_per_call,
                   " must be >= 1 (--threads_per_call=0 means one per core)");
  }
  if (config.tls_cert_pem.empty() != config.tls_key_pem.empty()) {
    return invalid("--tls_cert and --tls_key: give both or neither");
  }
  if (!config.tls_client_ca_pem.empty() && config.tls_cert_pem.empty()) {
    return invalid("--tls_client_ca needs --tls_cert and --tls_key");
  }
  if (config.max_queued < 0) {
    return invalid("--max_queued: ", config.max_queued, " must be >= 0 (0 = no request waits)");
  }
  if (config.worker_threads < 0) {
    return invalid("--worker_threads: ", config.worker_threads, " must be >= 0 (0 = one per core)");
  }
  if (config.idle_trim < absl::ZeroDuration()) {
    return invalid("--idle_trim_ms: ", absl::ToInt64Milliseconds(config.idle_trim),
                   " must be >= 0 (0 = never give memory back when idle)");
  }
  if (config.idle_trim_min_request_bytes < 0) {
    return invalid("idle_trim_min_request_bytes: ", config.idle_trim_min_request_bytes,
                   " must be >= 0");
  }
  if (config.max_memory_mb < 0) {
    return invalid("--max_memory_mb: ", config.max_memory_mb, " must be >= 0 (0 = no budget)");
  }
  if (config.max_memory_mb > 0 && config.max_memory_mb < 16) {
    return invalid("--max_memory_mb: ", config.max_memory_mb,
                   " is below 16 (gRPC alone needs a few MiB per connection)");
  }
  if (config.inline_max_bytes < 0) {
    return invalid("--inline_max_bytes: ", config.inline_max_bytes,
                   " must be >= 0 (0 = every request on a worker)");
  }
  if (config.http.port != -1) return ValidateHttpServerConfig(config.http);
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<KomaServer>> KomaServer::Start(const ServerConfig& config) {
  if (absl::Status valid = ValidateServerConfig(config); !valid.ok()) return valid;
  std::unique_ptr<KomaServer> server(new KomaServer());
  // The metrics port first: a bad --metrics_address fails before any gRPC port is bound.
  if (absl::Status s = server->StartMetrics(config); !s.ok()) return s;
  const int threads = config.worker_threads > 0 ? config.worker_threads : DefaultWorkerThreads();
  server->trimmer_ =
      std::make_unique<IdleTrimmer>(config.idle_trim, config.idle_trim_min_request_bytes);
  server->pool_ = std::make_unique<WorkerPool>(threads, static_cast<size_t>(config.max_queued));
  constexpr int64_t kMiB = 1024 * 1024;
  // See ServerConfig::max_memory_mb: a quarter for gRPC, half for calls.
  const int64_t grpc_share = config.max_memory_mb * kMiB / 4;
  const int64_t calls_share = config.max_memory_mb * kMiB / 2;
  if (config.max_memory_mb > 0) {
    server->budget_ = std::make_unique<MemoryBudget>(
        calls_share, absl::StrCat("memory budget (--max_memory_mb=", config.max_memory_mb, ", ",
                                  calls_share / kMiB, " MiB of it for calls)"));
    if (server->metrics_registry_ != nullptr) {
      server->budget_->ExportMetrics(*server->metrics_registry_);
    }
  }
  server->service_ = std::make_unique<RetimeService>(
      config.limits, server->pool_.get(), server->metrics_.get(), config.inline_max_bytes,
      server->trimmer_.get(), server->budget_.get());
  server->max_message_bytes_ = config.max_message_bytes;

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  if (!config.address.empty()) {
    builder.AddListeningPort(config.address, Credentials(config), &server->port_);
  }
  if (config.max_memory_mb > 0) {
    // gRPC's own memory (transport buffers, requests being received) under its quota: near
    // the quota it shrinks its flow-control windows, so senders wait instead of the server
    // buffering every request at once.
    grpc::ResourceQuota quota("koma_server");
    quota.Resize(static_cast<size_t>(grpc_share));
    builder.SetResourceQuota(quota);
  }
  builder.SetMaxReceiveMessageSize(config.max_message_bytes);
  builder.SetMaxSendMessageSize(config.max_message_bytes);
  builder.RegisterService(server->service_.get());
  server->server_ = builder.BuildAndStart();
  if (server->server_ == nullptr || (!config.address.empty() && server->port_ == 0)) {
    return absl::UnavailableError(absl::StrCat("--address: could not listen on ", config.address,
                                               " (in use, or not a valid host:port)"));
  }
  grpc::HealthCheckServiceInterface* health = server->server_->GetHealthCheckService();
  health->SetServingStatus(true);
  health->SetServingStatus(kServiceName, true);
  if (absl::Status s = server->StartHttp(config); !s.ok()) return s;
  return server;
}

absl::Status KomaServer::StartHttp(const ServerConfig& config) {
  if (config.http.port == -1) return absl::OkStatus();
  absl::StatusOr<std::unique_ptr<HttpServer>> http = HttpServer::Start(config.http);
  if (!http.ok()) return http.status();
  http_ = *std::move(http);
  RegisterConnectApi(*http_, InProcessChannel(), budget_.get());
  return absl::OkStatus();
}

absl::Status KomaServer::StartMetrics(const ServerConfig& config) {
  metrics_registry_ = config.metrics_registry;
  if (metrics_registry_ == nullptr && !config.metrics_address.empty()) {
    metrics_registry_ = std::make_shared<prometheus::Registry>();
  }
  if (metrics_registry_ == nullptr) return absl::OkStatus();
  metrics_ = std::make_unique<RpcMetrics>(*metrics_registry_);
  if (config.metrics_address.empty()) return absl::OkStatus();
  absl::StatusOr<std::unique_ptr<MetricsEndpoint>> endpoint =
      MetricsEndpoint::Start(config.metrics_address, metrics_registry_);
  if (!endpoint.ok()) return endpoint.status();
  metrics_endpoint_ = *std::move(endpoint);
  return absl::OkStatus();
}

KomaServer::~KomaServer() { Shutdown(absl::ZeroDuration()); }

std::shared_ptr<grpc::Channel> KomaServer::InProcessChannel() {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(max_message_bytes_);
  args.SetMaxSendMessageSize(max_message_bytes_);
  return server_->InProcessChannel(args);
}

void KomaServer::StopServing() {
  if (server_ != nullptr) server_->GetHealthCheckService()->SetServingStatus(false);
}

void KomaServer::Shutdown(absl::Duration grace) {
  if (shut_down_ || server_ == nullptr) return;
  shut_down_ = true;
  StopServing();
  if (service_ != nullptr) service_->EndLiveStreams();
  const auto deadline = std::chrono::system_clock::now() + absl::ToChronoMilliseconds(grace);
  // The HTTP port stops beside the gRPC drain: it stops accepting at once, and waits for its
  // requests in flight, whose in-process calls the drain answers or cancels; a kept-alive idle
  // connection holds its civetweb thread up to 2 s (civetweb's poll quantum), within the grace.
  std::thread http_stop([this] { http_.reset(); });
  server_->Shutdown(deadline);
  http_stop.join();
  pool_.reset();  // runs what was accepted; every reactor gets its Finish
  server_->Wait();
}

}  // namespace koma::server

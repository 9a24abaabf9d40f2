// Channels and deadlines shared by every `koma` subcommand.
#ifndef KOMA_CLIENT_CHANNEL_H_
#define KOMA_CLIENT_CHANNEL_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {

// Default server when --server is not given: $KOMA_SERVER, else 127.0.0.1:50051.
std::string DefaultServer();

// The gRPC target for a --server value: "a:p" as is; "a:p,b:p" as "ipv4:a:p,b:p" (or
// "ipv6:" when every address is bracketed); a URI ("dns:///name:p", "ipv4:...") as is.
// `balanced`: more than one address, or a resolver that may return several, so the channel
// should use round_robin. INVALID_ARGUMENT for an empty or mixed list.
struct ChannelTarget {
  std::string uri;
  bool balanced = false;
};
absl::StatusOr<ChannelTarget> ResolveTarget(const std::string& servers);

// TLS for every channel this process makes (--tls-ca, --tls-cert, --tls-key). Empty
// paths: plaintext. `ca`: the CA that signed the server's certificate (empty with a client
// certificate: the system's roots). NOT_FOUND / INVALID_ARGUMENT naming the file.
struct TlsFiles {
  std::string ca;
  std::string cert;
  std::string key;
};
absl::Status ConfigureTls(const TlsFiles& files);

// The service config of koma's own clients: when `balanced`, round_robin over the
// addresses whose grpc.health.v1 health for "koma.v1.Retime" is SERVING (a draining server
// drops out); always up to 3 attempts of a call that fails with UNAVAILABLE or CANCELLED (a
// server that is draining or gone), 0.1 s backoff doubling to 1 s.
std::string ClientServiceConfig(bool balanced);

// An insecure channel to `servers` (see ResolveTarget) whose message limits match the
// server's default (256 MiB), so large clips and their answers fit, with
// ClientServiceConfig. INVALID_ARGUMENT for a malformed list.
absl::StatusOr<std::shared_ptr<grpc::Channel>> MakeChannel(const std::string& servers);

// A Retime stub on MakeChannel(servers), or, within a ScopedRetimeChannel on this thread, on
// that scope's channel whatever `servers` says.
absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> NewRetimeStub(const std::string& servers);

// Sends this thread's Retime calls (NewRetimeStub) to `channel` until destroyed: koma_server
// runs the page's jobs through the CLI's commands on its own in-process channel
// (client/file_job.h), so they pass the service's limits and admission as any call.
class ScopedRetimeChannel {
 public:
  explicit ScopedRetimeChannel(std::shared_ptr<grpc::Channel> channel);
  ~ScopedRetimeChannel();
  ScopedRetimeChannel(const ScopedRetimeChannel&) = delete;
  ScopedRetimeChannel& operator=(const ScopedRetimeChannel&) = delete;

 private:
  std::shared_ptr<grpc::Channel> channel_;
  const std::shared_ptr<grpc::Channel>* previous_;
};

// Every RPC carries a deadline: now + `seconds`.
void SetDeadline(grpc::ClientContext* context, double seconds);

// Prints "koma: message" to stderr and returns exit code 1 (a local failure: files, flags).
int ReportError(const absl::Status& status);

// Prints "koma: CODE: message" to stderr and returns exit code 1.
int ReportRpcError(const grpc::Status& status);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CHANNEL_H_

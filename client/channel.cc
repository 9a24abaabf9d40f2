#include "client/channel.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/command_io.h"

namespace koma::client {
namespace {

constexpr int kMaxMessageBytes = 256 * 1024 * 1024;

// Set once by ConfigureTls before any channel is made.
std::shared_ptr<grpc::ChannelCredentials>& Credentials() {
  static std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  return credentials;
}

absl::StatusOr<std::string> ReadPem(absl::string_view flag, const std::string& path) {
  if (path.empty()) return std::string();
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || text.str().empty()) {
    return absl::NotFoundError(absl::StrCat(flag, ": cannot read ", path));
  }
  return text.str();
}

bool IsIpv4HostPort(const std::string& address) {
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  return std::all_of(address.begin(), address.begin() + colon,
                     [](char c) { return (c >= '0' && c <= '9') || c == '.'; });
}

}  // namespace

std::string DefaultServer() {
  const char* from_env = std::getenv("KOMA_SERVER");
  return (from_env != nullptr && *from_env != '\0') ? from_env : "127.0.0.1:50051";
}

absl::StatusOr<ChannelTarget> ResolveTarget(const std::string& servers) {
  if (servers.empty()) return absl::InvalidArgumentError("server list: empty");
  if (absl::StrContains(servers, ":///") || absl::StartsWith(servers, "ipv4:") ||
      absl::StartsWith(servers, "ipv6:") || absl::StartsWith(servers, "unix:")) {
    return ChannelTarget{servers,
                         absl::StrContains(servers, ",") || absl::StartsWith(servers, "dns:")};
  }
  const std::vector<std::string> addresses = absl::StrSplit(servers, ',', absl::SkipEmpty());
  if (addresses.size() == 1) return ChannelTarget{addresses[0], false};
  const bool all_v6 = std::all_of(addresses.begin(), addresses.end(),
                                  [](const std::string& a) { return absl::StartsWith(a, "["); });
  const bool all_v4 = std::all_of(addresses.begin(), addresses.end(), IsIpv4HostPort);
  if (!all_v6 && !all_v4) {
    return absl::InvalidArgumentError(absl::StrCat(
        "server list: must be all IPv4 (127.0.0.1:p,127.0.0.1:q) or all bracketed IPv6 "
        "([::1]:p,[::1]:q); for names use dns:///name:port, got \"",
        servers, "\""));
  }
  return ChannelTarget{absl::StrCat(all_v6 ? "ipv6:" : "ipv4:", absl::StrJoin(addresses, ",")),
                       true};
}

absl::Status ConfigureTls(const TlsFiles& files) {
  if (files.ca.empty() && files.cert.empty() && files.key.empty()) return absl::OkStatus();
  if (files.cert.empty() != files.key.empty()) {
    return absl::InvalidArgumentError("--tls-cert and --tls-key: give both or neither");
  }
  grpc::SslCredentialsOptions options;
  absl::StatusOr<std::string> ca = ReadPem("--tls-ca", files.ca);
  absl::StatusOr<std::string> cert = ReadPem("--tls-cert", files.cert);
  absl::StatusOr<std::string> key = ReadPem("--tls-key", files.key);
  for (const auto* pem : {&ca, &cert, &key}) {
    if (!pem->ok()) return pem->status();
  }
  options.pem_root_certs = *ca;
  options.pem_cert_chain = *cert;
  options.pem_private_key = *key;
  Credentials() = grpc::SslCredentials(options);
  return absl::OkStatus();
}

std::string ClientServiceConfig(bool balanced) {
  // Every koma.v1.Retime RPC is a pure function of its request, so a second attempt on
  // another server is always safe. CANCELLED is retried too because gRPC's server answers
  // CANCELLED, not UNAVAILABLE, to a call that reaches it after its shutdown began
  // (grpc/grpc#41785); gRPC never retries a call the application itself cancelled.
  const std::string retry =
      R"("methodConfig":[{"name":[{"service":"koma.v1.Retime"}],)"
      R"("retryPolicy":{"maxAttempts":3,"initialBackoff":"0.1s","maxBackoff":"1s",)"
      R"("backoffMultiplier":2,"retryableStatusCodes":["UNAVAILABLE","CANCELLED"]}}])";
  // Balanced: round_robin over the servers whose health (grpc.health.v1 Watch) says
  // SERVING, so a server that got SIGTERM (NOT_SERVING for --shutdown_delay_ms before it
  // stops accepting) gets no new calls.
  return balanced
             ? absl::StrCat(R"({"loadBalancingConfig":[{"round_robin":{}}],)",
                            R"("healthCheckConfig":{"serviceName":"koma.v1.Retime"},)", retry, "}")
             : absl::StrCat("{", retry, "}");
}

absl::StatusOr<std::shared_ptr<grpc::Channel>> MakeChannel(const std::string& servers) {
  absl::StatusOr<ChannelTarget> target = ResolveTarget(servers);
  if (!target.ok()) return target.status();
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(kMaxMessageBytes);
  args.SetMaxSendMessageSize(kMaxMessageBytes);
  args.SetServiceConfigJSON(ClientServiceConfig(target->balanced));
  return grpc::CreateCustomChannel(target->uri, Credentials(), args);
}

namespace {
thread_local const std::shared_ptr<grpc::Channel>* scoped_channel = nullptr;
}  // namespace

ScopedRetimeChannel::ScopedRetimeChannel(std::shared_ptr<grpc::Channel> channel)
    : channel_(std::move(channel)), previous_(scoped_channel) {
  scoped_channel = &channel_;
}

ScopedRetimeChannel::~ScopedRetimeChannel() { scoped_channel = previous_; }

absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> NewRetimeStub(const std::string& servers) {
  if (scoped_channel != nullptr) return v1::Retime::NewStub(*scoped_channel);
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = MakeChannel(servers);
  if (!channel.ok()) return channel.status();
  return v1::Retime::NewStub(*channel);
}

void SetDeadline(grpc::ClientContext* context, double seconds) {
  const auto timeout = std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::duration<double>(seconds));
  context->set_deadline(std::chrono::system_clock::now() + timeout);
}

int ReportError(const absl::Status& status) {
  PrintStderr(absl::StrCat("koma: ", status.message(), "\n"));
  return 1;
}

int ReportRpcError(const grpc::Status& status) {
  // absl's canonical code names are gRPC's ("INVALID_ARGUMENT", ...).
  const std::string code =
      absl::StatusCodeToString(static_cast<absl::StatusCode>(status.error_code()));
  PrintStderr(absl::StrCat("koma: ", code, ": ", status.error_message(), "\n"));
  return 1;
}

}  // namespace koma::client

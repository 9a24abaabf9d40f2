#include "client/channel.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "absl/status/status.h"

namespace koma::client {
namespace {

constexpr int kMaxMessageBytes = 256 * 1024 * 1024;

}  // namespace

std::string DefaultServer() {
  const char* from_env = std::getenv("KOMA_SERVER");
  return (from_env != nullptr && *from_env != '\0') ? from_env : "127.0.0.1:50051";
}

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(kMaxMessageBytes);
  args.SetMaxSendMessageSize(kMaxMessageBytes);
  return grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args);
}

void SetDeadline(grpc::ClientContext* context, double seconds) {
  const auto timeout = std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::duration<double>(seconds));
  context->set_deadline(std::chrono::system_clock::now() + timeout);
}

int ReportRpcError(const grpc::Status& status) {
  // absl's canonical code names are gRPC's ("INVALID_ARGUMENT", ...).
  const std::string code =
      absl::StatusCodeToString(static_cast<absl::StatusCode>(status.error_code()));
  std::fprintf(stderr, "koma: %s: %s\n", code.c_str(),
               status.error_message().c_str());
  return 1;
}

}  // namespace koma::client

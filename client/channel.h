// Channels and deadlines shared by every `koma` subcommand.
#ifndef KOMA_CLIENT_CHANNEL_H_
#define KOMA_CLIENT_CHANNEL_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace koma::client {

// Default server when --server is not given: $KOMA_SERVER, else 127.0.0.1:50051.
std::string DefaultServer();

// An insecure channel to `target` ("host:port", "dns:///name:port") whose message limits
// match the server's default (256 MiB), so large clips and their answers fit.
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target);

// Every RPC carries a deadline: now + `seconds`.
void SetDeadline(grpc::ClientContext* context, double seconds);

// Prints "koma: CODE: message" to stderr and returns exit code 1.
int ReportRpcError(const grpc::Status& status);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CHANNEL_H_

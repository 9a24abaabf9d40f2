#include "client/health_command.h"

#include <cstdio>

#include "client/channel.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace koma::client {

int RunHealth(const HealthArgs& args) {
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = MakeChannel(args.server);
  if (!channel.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(channel.status().message()).c_str());
    return 1;
  }
  auto stub = grpc::health::v1::Health::NewStub(*channel);
  grpc::ClientContext context;
  SetDeadline(&context, args.deadline_seconds);
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(args.service);
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  if (!status.ok()) return ReportRpcError(status);
  const std::string name =
      grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status());
  std::printf("%s\n", name.c_str());
  return response.status() == grpc::health::v1::HealthCheckResponse::SERVING ? 0 : 1;
}

}  // namespace koma::client

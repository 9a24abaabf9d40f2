#include "client/health_command.h"

#include <cstdio>

#include "client/channel.h"
#include "client/command_output.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace koma::client {

int RunHealth(const HealthArgs& args) {
  // The state is the result: it goes to stdout even where other commands' summaries go to
  // stderr (--json puts it in the object instead).
  const CommandOutput out("health", args.json, args.quiet, args.server);
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = MakeChannel(args.server);
  if (!channel.ok()) return out.UsageFailure(channel.status());
  auto stub = grpc::health::v1::Health::NewStub(*channel);
  grpc::ClientContext context;
  SetDeadline(&context, args.deadline_seconds);
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(args.service);
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  if (!status.ok()) return out.RpcFailure(status);
  const std::string name =
      grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status());
  if (args.json) {
    // "status" is the serving status itself, not "ok": a script reading it must not see a
    // server that answers NOT_SERVING as healthy (the exit code says the same).
    out.Success("",
                {{"status", name},
                 {"server", args.server},
                 {"service", args.service},
                 {"serving_status", name}},
                false);
  } else if (!args.quiet) {
    std::printf("%s\n", name.c_str());
  }
  return response.status() == grpc::health::v1::HealthCheckResponse::SERVING ? kExitOk
                                                                             : kExitFailure;
}

}  // namespace koma::client

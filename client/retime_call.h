// The one unary call of `koma skeletal`, `curves` and `lipblink`: a Retime stub on --server,
// --deadline, the call, and its failure reported the command's way.
#ifndef KOMA_CLIENT_RETIME_CALL_H_
#define KOMA_CLIENT_RETIME_CALL_H_

#include <grpcpp/grpcpp.h>

#include <memory>

#include "absl/status/statusor.h"
#include "client/call_flags.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {

// Calls `method` (&v1::Retime::Stub::RetimeCurves, ...) with `request` on flags.server, with
// flags.deadline_seconds. -1 when `response` holds the answer; else the exit code, the failure
// printed by `out`: 2 for a malformed --server, 1 for a failed RPC (RpcErrorText).
template <typename Request, typename Response>
int CallRetime(const CallFlags& flags, const CommandOutput& out,
               grpc::Status (v1::Retime::Stub::*method)(grpc::ClientContext*, const Request&,
                                                        Response*),
               const Request& request, Response* response) {
  absl::StatusOr<std::unique_ptr<v1::Retime::Stub>> stub = NewRetimeStub(flags.server);
  if (!stub.ok()) return out.UsageFailure(stub.status());
  grpc::ClientContext context;
  SetDeadline(&context, flags.deadline_seconds);
  const grpc::Status status = ((**stub).*method)(&context, request, response);
  if (!status.ok()) return out.RpcFailure(status);
  return -1;
}

}  // namespace koma::client

#endif  // KOMA_CLIENT_RETIME_CALL_H_

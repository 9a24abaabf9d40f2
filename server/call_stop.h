// When a call's work must stop before it is done (core/stop_check.h): its client's deadline
// has passed, the client cancelled it or went away, gRPC cancelled it because the server's
// shutdown grace ran out, or it has run --max_call_seconds. The service installs one around
// every handler (retime_service.cc) and asks it again once the handler returns: a stopped
// call is answered with the signal's status, whatever its handler left behind.
#ifndef KOMA_SERVER_CALL_STOP_H_
#define KOMA_SERVER_CALL_STOP_H_

#include <grpcpp/server_context.h>

#include <chrono>

#include "absl/status/status.h"
#include "core/stop_check.h"

namespace koma::server {

class CallStopSignal final : public StopSignal {
 public:
  // `context` must outlive the signal; `start` is when the call arrived; `max_call_seconds`
  // 0 means no server-side bound.
  CallStopSignal(const grpc::ServerContextBase* context,
                 std::chrono::steady_clock::time_point start, double max_call_seconds);

  // DEADLINE_EXCEEDED (the client's deadline, or --max_call_seconds), CANCELLED, or OK.
  absl::Status Reason() const override;

 private:
  const grpc::ServerContextBase* context_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::system_clock::time_point client_deadline_;
  std::chrono::steady_clock::time_point server_deadline_;
  double max_call_seconds_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_CALL_STOP_H_

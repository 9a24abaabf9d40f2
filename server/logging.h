// Server logging on spdlog (stderr): plain text, or one JSON object per line for log
// pipelines. spdlog 1.10 has no JSON formatter, so JSON lines are built with nlohmann::json,
// which escapes every string.
#ifndef KOMA_SERVER_LOGGING_H_
#define KOMA_SERVER_LOGGING_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include <grpcpp/support/status.h>

namespace grpc {
class CallbackServerContext;
}

namespace koma::server {

enum class LogFormat { kText, kJson };

// `level`: trace, debug, info, warn, error, critical or off. `format`: text or json.
// INVALID_ARGUMENT naming the flag on an unknown value.
absl::Status ConfigureLogging(absl::string_view level, absl::string_view format);

// One line per finished RPC.
struct RpcRecord {
  absl::string_view method;  // "RetimeSkeletal"
  std::string peer;         // "ipv4:127.0.0.1:53422"
  std::string request_id;   // x-request-id: the caller's, or generated
  int64_t frames = 0;       // input frames, 0 if the request was rejected before parsing
  int64_t joints = 0;       // RetimeSkeletal
  int64_t curves = 0;       // RetimeCurves, LipBlink
  int64_t bytes_in = 0;     // serialized request size
  int64_t bytes_out = 0;    // serialized response size, 0 on error
  grpc::StatusCode code = grpc::StatusCode::OK;
  std::string error;        // status message when not OK
  double latency_ms = 0.0;  // from the handler's start to Finish
  // Where the request's file bent a rule and was read anyway: the line is then a warning.
  std::vector<std::string> warnings;
};
void LogRpc(const RpcRecord& record);
// The call's x-request-id: the caller's (cut to 128 bytes), or a new one of 16 hex digits from
// a SplitMix64 stream seeded once from the clock; sent back in the initial metadata, so a
// client log and a server log can be joined.
std::string TakeRequestId(grpc::CallbackServerContext* context);
// Whether LogRpc writes a line for `record` at the configured level: what is only needed for
// the line (the peer's address) is looked up only then.
bool RpcLineLogged(const RpcRecord& record);

// Lifecycle messages (listening, shutting down): info level, or warn when `warning`.
void LogEvent(absl::string_view message, bool warning = false);

}  // namespace koma::server

#endif  // KOMA_SERVER_LOGGING_H_

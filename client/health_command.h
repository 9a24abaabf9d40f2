// `koma health [--service NAME]`: asks grpc.health.v1.Health/Check; exit 0 only if SERVING.
#ifndef KOMA_CLIENT_HEALTH_COMMAND_H_
#define KOMA_CLIENT_HEALTH_COMMAND_H_

#include <string>

#include "client/call_flags.h"

namespace koma::client {

// --json: {"status": "SERVING", "serving_status": "SERVING", ...} (status is the serving
// status: SERVING, NOT_SERVING, UNKNOWN or SERVICE_UNKNOWN; "error" when the call failed); --quiet: print nothing, the exit
// code tells. A health check's deadline is short: 5 s.
struct HealthArgs : CallFlags {
  HealthArgs() { deadline_seconds = 5.0; }
  std::string service;  // "" = the whole server
};

// Prints SERVING / NOT_SERVING / ... to stdout. Exit code 0 when SERVING, 1 otherwise.
int RunHealth(const HealthArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_HEALTH_COMMAND_H_

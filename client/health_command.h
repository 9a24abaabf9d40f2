// `koma health [--service NAME]`: asks grpc.health.v1.Health/Check; exit 0 only if SERVING.
#ifndef KOMA_CLIENT_HEALTH_COMMAND_H_
#define KOMA_CLIENT_HEALTH_COMMAND_H_

#include <string>

namespace koma::client {

struct HealthArgs {
  std::string server;   // host:port
  std::string service;  // "" = the whole server
  double deadline_seconds = 5.0;
  bool json = false;   // --json: {"status": "ok", "serving_status": "SERVING", ...}
  bool quiet = false;  // --quiet: print nothing; the exit code tells
};

// Prints SERVING / NOT_SERVING / ... to stdout. Exit code 0 when SERVING, 1 otherwise.
int RunHealth(const HealthArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_HEALTH_COMMAND_H_

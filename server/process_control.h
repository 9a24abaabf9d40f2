// Process plumbing shared by koma_server and the benchmark servers (koma_echo_server,
// koma_api_server): the port file scripts wait for, and stop signals taken synchronously.
#ifndef KOMA_SERVER_PROCESS_CONTROL_H_
#define KOMA_SERVER_PROCESS_CONTROL_H_

#include <pthread.h>
#include <signal.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace koma::server {

// Writes `port` to `path` through a temporary file and a rename, so a reader never sees it
// half written.
inline bool WritePortFile(const std::string& path, int port) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    if (!(out << port << '\n')) return false;
  }
  return std::rename(temporary.c_str(), path.c_str()) == 0;
}

// SIGTERM and SIGINT, blocked in the constructing thread and every thread it starts later
// (gRPC's threads inherit the mask), so they are only ever taken by Wait(), never by a
// handler running inside gRPC code. Construct first thing in main().
class StopSignals {
 public:
  StopSignals() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGTERM);
    sigaddset(&signals_, SIGINT);
    pthread_sigmask(SIG_BLOCK, &signals_, nullptr);
  }

  // Blocks until one of them arrives; returns SIGTERM or SIGINT.
  int Wait() {
    int signal_number = 0;
    sigwait(&signals_, &signal_number);
    return signal_number;
  }

 private:
  sigset_t signals_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_PROCESS_CONTROL_H_

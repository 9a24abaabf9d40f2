// A real koma server with no listening port, reached through its in-process channel.
#ifndef KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_
#define KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_

#include <chrono>
#include <memory>

#include "koma/v1/retime.grpc.pb.h"
#include "server/server.h"

namespace koma::testing {

class InProcessServer {
 public:
  // `config.address` is ignored: no port is opened.
  explicit InProcessServer(server::ServerConfig config = {}) {
    config.address = "";
    server_ = server::KomaServer::Start(config).value();
    stub_ = v1::Retime::NewStub(server_->InProcessChannel());
  }
  static server::ServerConfig Config(int worker_threads, int64_t max_values) {
    server::ServerConfig config;
    config.worker_threads = worker_threads;
    config.limits.max_values = max_values;
    return config;
  }

  server::KomaServer& server() { return *server_; }
  v1::Retime::Stub& stub() { return *stub_; }

 private:
  std::unique_ptr<server::KomaServer> server_;
  std::unique_ptr<v1::Retime::Stub> stub_;
};

// Every test RPC gets a deadline, so a broken server fails a test instead of hanging it.
inline void SetTestDeadline(grpc::ClientContext& context, int seconds = 30) {
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(seconds));
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_IN_PROCESS_SERVER_H_

// Sends one serialised request over and over to koma: closed loop (a fixed number of calls
// outstanding) or open loop (a fixed schedule of sends), over several channels.
#ifndef KOMA_BENCH_LOAD_LOAD_RUNNER_H_
#define KOMA_BENCH_LOAD_LOAD_RUNNER_H_

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "bench/load/load_options.h"
#include "bench/load/load_request.h"
#include "client/channel.h"

namespace koma::load {

// --target resolves like the koma client's --server (client/channel.h).
using client::ChannelTarget;
using client::ResolveTarget;

// `count` distinct channels (separate connections) with 256 MiB message limits and the
// koma client's service config (client::ClientServiceConfig: round_robin when
// `target.balanced`, retries).
std::vector<std::shared_ptr<grpc::Channel>> MakeChannels(const ChannelTarget& target, int count);

struct RunResult {
  std::vector<double> latencies_ms;       // successful measured calls, milliseconds
  std::map<std::string, int64_t> errors;  // failed measured calls by status code name
  int64_t warmup_calls = 0;               // calls sent during the warmup (not in the statistics)
  double measured_s = 0.0;                // seconds from the end of the warmup to the last reply
  bool hit_time_cap = false;              // stopped by --max-duration before --count
  // Serialised response sizes of the successful measured calls, bytes: a baseline is only
  // comparable when these match.
  int64_t response_bytes_min = 0;
  int64_t response_bytes_max = 0;
  // Successful measured calls by the server that answered them, as gRPC names it
  // ("ipv4:127.0.0.1:50051"): with a server list, the calls per backend.
  std::map<std::string, int64_t> ok_by_peer;
};

// Runs the load described by `options` with `request` on `channels` and waits for every
// call to finish (each has a deadline, so this is bounded too).
RunResult RunLoad(const LoadOptions& options, const LoadRequest& request,
                  const std::vector<std::shared_ptr<grpc::Channel>>& channels);

}  // namespace koma::load

#endif  // KOMA_BENCH_LOAD_LOAD_RUNNER_H_

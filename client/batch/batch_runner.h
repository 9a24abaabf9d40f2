// The batch engine: a small pool reads and parses clips and writes answers while up to
// `jobs` calls are in flight over one channel per server; calls that fail with UNAVAILABLE
// or RESOURCE_EXHAUSTED are sent again (bounded, with backoff), to another server when
// there is one; Ctrl-C stops after the calls in flight.
#ifndef KOMA_CLIENT_BATCH_BATCH_RUNNER_H_
#define KOMA_CLIENT_BATCH_BATCH_RUNNER_H_

#include <functional>
#include <string>
#include <vector>

#include "client/batch/batch_inputs.h"
#include "client/batch/batch_progress.h"
#include "client/batch/batch_rpc.h"

namespace koma::client::batch {

struct RunnerSettings {
  std::vector<std::string> servers;  // one channel each ("host:port" or a gRPC target URI)
  int jobs = 0;                      // calls in flight; 0: 2 per server
  int io_threads = 4;                // threads that read/parse inputs and write outputs
  int max_attempts = 8;              // per clip, for UNAVAILABLE / RESOURCE_EXHAUSTED
  double deadline_seconds = 60.0;    // per attempt
  bool verbose = false;              // a line per clip written
};

enum class ItemStatus { kNotDone, kUpToDate, kOk, kFailed };

struct ItemResult {
  ItemStatus status = ItemStatus::kNotDone;
  std::string code;    // gRPC/absl code name of a failure ("INVALID_ARGUMENT")
  std::string error;   // the message, naming the file
  int attempts = 0;    // calls sent
  std::string server;  // of the last call
};

struct RunResult {
  std::vector<ItemResult> items;  // parallel to the batch's items
  Counts counts;
  bool interrupted = false;  // Ctrl-C (SIGINT) or SIGTERM stopped it
  double seconds = 0;
};

// Runs the clips whose `results[i].status` is kNotDone (the others, up to date, are counted
// as such). `on_written(i)` runs (on a pool thread, under the runner's lock) after clip i's
// outputs are in place. SIGINT/SIGTERM: the first stops sending new calls and lets the calls
// in flight finish and be written; the second cancels them. The handlers are restored after.
RunResult RunBatch(const std::vector<BatchItem>& items, std::vector<ItemResult> results,
                   const Rpc& rpc, const RunnerSettings& settings, Progress& progress,
                   const std::function<void(size_t)>& on_written);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_RUNNER_H_

// Gives the memory that large calls leave in malloc's heap back to the system once the server
// goes idle. A burst of large calls (RetimeCurves 500 curves x 10k frames, four at a time)
// leaves ~300 MiB resident at rest in glibc's heap: free, but in chunks between live ones, so
// the heap's top is never trimmed (platform/malloc_tuning.h). malloc_trim(0) releases those
// pages (measured: 318 -> 19 MiB). Trimming after every large call instead cost a third of its
// latency (the next call faults the pages in again), so it waits for a quiet moment.
#ifndef KOMA_SERVER_IDLE_TRIM_H_
#define KOMA_SERVER_IDLE_TRIM_H_

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "absl/time/time.h"

namespace koma::server {

class IdleTrimmer {
 public:
  // Trims when, over a whole `idle` period, no call was in flight and none started, and at
  // least `min_request_bytes` of requests arrived since the last trim (small calls leave
  // nothing worth a trim). A zero `idle` turns it off: no thread, no trims.
  IdleTrimmer(absl::Duration idle, int64_t min_request_bytes);
  // Stops the thread (at most one `idle` period's wait).
  ~IdleTrimmer();

  IdleTrimmer(const IdleTrimmer&) = delete;
  IdleTrimmer& operator=(const IdleTrimmer&) = delete;

  // Every call, from the moment its request is received until it is answered.
  void CallStarted(int64_t request_bytes);
  void CallFinished();

  // How many times it has trimmed (tests, logs).
  int64_t trims() const { return trims_.load(std::memory_order_relaxed); }

 private:
  void Loop();

  const absl::Duration idle_;
  const int64_t min_request_bytes_;
  std::atomic<int64_t> in_flight_{0};
  std::atomic<uint64_t> started_{0};
  std::atomic<int64_t> bytes_since_trim_{0};
  std::atomic<int64_t> trims_{0};
  std::mutex mutex_;
  std::condition_variable stop_requested_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_IDLE_TRIM_H_

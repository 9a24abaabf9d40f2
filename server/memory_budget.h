// A server-wide bound on the memory all calls in flight may hold together (--max_memory_mb).
//
// Each call reserves what it is expected to hold before it runs (its received bytes, the
// parsed request, the working arrays and the response: server/call_footprint.h) and gives it
// back when it finishes. A call whose reservation does not fit is answered RESOURCE_EXHAUSTED
// at once, naming the budget, instead of being run and driving the process into the OOM
// killer. What gRPC itself holds (receive buffers, messages being assembled) is bounded
// separately by its ResourceQuota (server/server.cc), with a share of the same budget.
#ifndef KOMA_SERVER_MEMORY_BUDGET_H_
#define KOMA_SERVER_MEMORY_BUDGET_H_

#include <prometheus/counter.h>
#include <prometheus/gauge.h>
#include <prometheus/registry.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::server {

class MemoryBudget {
 public:
  // `capacity_bytes` > 0: what calls in flight may reserve together. `name` starts each
  // refusal's message: the setting it comes from.
  explicit MemoryBudget(int64_t capacity_bytes, std::string name = "memory budget")
      : capacity_(capacity_bytes), name_(std::move(name)) {}

  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

  // Bytes reserved by one call, given back when it is destroyed (or Released).
  class Reservation {
   public:
    Reservation() = default;
    Reservation(Reservation&& other) noexcept { *this = std::move(other); }
    Reservation& operator=(Reservation&& other) noexcept;
    ~Reservation() { Release(); }

    int64_t bytes() const { return bytes_; }
    // False for a default-constructed reservation (no budget).
    bool budgeted() const { return budget_ != nullptr; }
    // Grows (or shrinks) the reservation to `bytes`; RESOURCE_EXHAUSTED, the reservation
    // unchanged, when the growth does not fit. A default-constructed one has no budget and
    // always succeeds.
    absl::Status Resize(int64_t bytes, const char* what);
    void Release();

   private:
    friend class MemoryBudget;
    MemoryBudget* budget_ = nullptr;
    int64_t bytes_ = 0;
  };

  // A reservation of `bytes`, or RESOURCE_EXHAUSTED naming the budget, what `what` needs and
  // what is in use: "<name>: <what> needs 100 MiB, 380 MiB of 384 MiB are held by calls in
  // flight; retry with backoff".
  absl::StatusOr<Reservation> Reserve(int64_t bytes, const char* what);

  // Registers, in `registry` (which must outlive this budget), and keeps up to date:
  //   koma_memory_budget_bytes           the capacity (gauge)
  //   koma_memory_budget_in_use_bytes    reserved by calls in flight (gauge)
  //   koma_memory_budget_refused_total   calls answered RESOURCE_EXHAUSTED by it (counter)
  // Call before the first reservation.
  void ExportMetrics(prometheus::Registry& registry);

  int64_t capacity() const { return capacity_; }
  int64_t in_use() const { return in_use_.load(std::memory_order_relaxed); }
  // Reservations refused so far.
  int64_t refused() const { return refused_.load(std::memory_order_relaxed); }

 private:
  // Adds `bytes` to in_use_ if the sum stays within capacity_.
  bool TryTake(int64_t bytes);
  void Give(int64_t bytes);
  absl::Status Refusal(int64_t bytes, const char* what);

  const int64_t capacity_;
  const std::string name_;
  std::atomic<int64_t> in_use_{0};
  std::atomic<int64_t> refused_{0};
  prometheus::Gauge* in_use_gauge_ = nullptr;
  prometheus::Counter* refused_counter_ = nullptr;
};

// The default --max_memory_mb: three quarters of the memory this process may use, which is
// the container's cgroup limit when there is one (cgroup v2 memory.max, v1
// memory.limit_in_bytes) and else the machine's MemTotal. The rest is left for the process'
// own code, gRPC's threads and malloc's slack. `root` is where /proc and /sys are (tests).
int64_t DefaultMemoryBudgetMb(const std::string& root = "");

}  // namespace koma::server

#endif  // KOMA_SERVER_MEMORY_BUDGET_H_

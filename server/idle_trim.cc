#include "server/idle_trim.h"

#include <malloc.h>

#include <chrono>

namespace koma::server {

IdleTrimmer::IdleTrimmer(absl::Duration idle, int64_t min_request_bytes)
    : idle_(idle), min_request_bytes_(min_request_bytes) {
  if (idle_ > absl::ZeroDuration()) thread_ = std::thread([this] { Loop(); });
}

IdleTrimmer::~IdleTrimmer() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  stop_requested_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void IdleTrimmer::CallStarted(int64_t request_bytes) {
  in_flight_.fetch_add(1, std::memory_order_relaxed);
  started_.fetch_add(1, std::memory_order_relaxed);
  bytes_since_trim_.fetch_add(request_bytes, std::memory_order_relaxed);
}

void IdleTrimmer::CallFinished() { in_flight_.fetch_sub(1, std::memory_order_relaxed); }

void IdleTrimmer::Loop() {
  const auto period = absl::ToChronoNanoseconds(idle_);
  std::unique_lock<std::mutex> lock(mutex_);
  uint64_t started_before = started_.load(std::memory_order_relaxed);
  while (!stop_requested_.wait_for(lock, period, [this] { return stopping_; })) {
    const uint64_t started_now = started_.load(std::memory_order_relaxed);
    const bool quiet = started_now == started_before &&
                       in_flight_.load(std::memory_order_relaxed) == 0;
    started_before = started_now;
    if (!quiet || bytes_since_trim_.load(std::memory_order_relaxed) < min_request_bytes_) {
      continue;
    }
    // A call that arrives now waits for the trim (malloc's lock) for a few milliseconds.
    bytes_since_trim_.store(0, std::memory_order_relaxed);
    malloc_trim(0);
    trims_.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace koma::server

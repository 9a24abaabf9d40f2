#include "server/worker_pool.h"

#include <utility>

namespace koma::server {

WorkerPool::WorkerPool(int threads, size_t max_queued) : max_queued_(max_queued) {
  if (threads < 1) threads = 1;
  threads_.reserve(threads);
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Loop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

WorkerPool::Submission WorkerPool::TrySubmit(std::function<void()> task) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return Submission::kStopping;
    // The first idle_ tasks of the queue are (about to be) taken by the idle workers; the
    // rest wait, and this one would be the next of those.
    const size_t waiting = queue_.size() > idle_ ? queue_.size() - idle_ : 0;
    if (queue_.size() >= idle_ && waiting >= max_queued_) return Submission::kQueueFull;
    queue_.push_back(std::move(task));
  }
  ready_.notify_one();
  return Submission::kAccepted;
}

void WorkerPool::Loop() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      ++idle_;
      ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      --idle_;
      if (queue_.empty()) return;  // stopping and drained
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    task();
  }
}

}  // namespace koma::server

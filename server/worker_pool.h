// A fixed set of threads that run RPC work off gRPC's callback threads, with a bounded
// queue so overload is answered with RESOURCE_EXHAUSTED instead of unbounded memory.
#ifndef KOMA_SERVER_WORKER_POOL_H_
#define KOMA_SERVER_WORKER_POOL_H_

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace koma::server {

class WorkerPool {
 public:
  // `threads` >= 1 workers. A task that finds a worker idle starts at once; at most
  // `max_queued` others wait for one (0: none wait).
  WorkerPool(int threads, size_t max_queued);
  // Runs every task already accepted, then joins.
  ~WorkerPool();

  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  enum class Submission { kAccepted, kQueueFull, kStopping };
  // kQueueFull or kStopping (and `task` dropped) when it would wait beyond max_queued or the
  // pool is being destroyed.
  Submission TrySubmit(std::function<void()> task);

 private:
  void Loop();

  const size_t max_queued_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> queue_;  // accepted, not yet taken by a worker
  size_t idle_ = 0;                           // workers waiting for a task
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_WORKER_POOL_H_

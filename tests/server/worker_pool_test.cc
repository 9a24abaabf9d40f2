#include "server/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace koma::server {
namespace {

using Submission = WorkerPool::Submission;

// A task that blocks its worker until Open(); Started() waits (up to 10 s) until a worker
// runs it.
class Gate {
 public:
  std::function<void()> Task() {
    return [this] {
      std::unique_lock<std::mutex> lock(mutex_);
      started_ = true;
      changed_.notify_all();
      changed_.wait(lock, [this] { return open_; });
    };
  }
  bool Started() {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(10), [this] { return started_; });
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool started_ = false;
  bool open_ = false;
};

TEST(WorkerPoolTest, RunsEveryAcceptedTaskBeforeDestruction) {
  std::atomic<int> done{0};
  {
    WorkerPool pool(2, 100);
    for (int i = 0; i < 50; ++i) ASSERT_EQ(pool.TrySubmit([&] { ++done; }), Submission::kAccepted);
  }
  EXPECT_EQ(done.load(), 50);
}

TEST(WorkerPoolTest, RejectsWhenTheQueueIsFull) {
  Gate running;
  WorkerPool pool(1, 1);
  ASSERT_EQ(pool.TrySubmit(running.Task()), Submission::kAccepted);
  ASSERT_TRUE(running.Started());                               // the worker holds task 1
  EXPECT_EQ(pool.TrySubmit([] {}), Submission::kAccepted);      // waits in the queue
  EXPECT_EQ(pool.TrySubmit([] {}), Submission::kQueueFull);     // a queue of 1 is full
  running.Open();
}

// --max_queued=0 means "none wait", not "nothing runs": a task that finds the worker idle
// starts (before, every task was refused); one that would wait is refused.
TEST(WorkerPoolTest, AZeroQueueStillRunsTasksOnIdleWorkers) {
  Gate running;
  WorkerPool pool(1, 0);
  // The worker is idle a moment after the pool is built: submit until it takes the task.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  Submission first = pool.TrySubmit(running.Task());
  while (first != Submission::kAccepted && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    first = pool.TrySubmit(running.Task());
  }
  ASSERT_EQ(first, Submission::kAccepted);
  ASSERT_TRUE(running.Started());
  EXPECT_EQ(pool.TrySubmit([] {}), Submission::kQueueFull);
  running.Open();
}

}  // namespace
}  // namespace koma::server

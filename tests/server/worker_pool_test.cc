#include "server/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>

namespace koma::server {
namespace {

TEST(WorkerPoolTest, RunsEveryAcceptedTaskBeforeDestruction) {
  std::atomic<int> done{0};
  {
    WorkerPool pool(2, 100);
    for (int i = 0; i < 50; ++i) ASSERT_TRUE(pool.TrySubmit([&] { ++done; }));
  }
  EXPECT_EQ(done.load(), 50);
}

TEST(WorkerPoolTest, RejectsWhenTheQueueIsFull) {
  std::mutex mutex;
  std::condition_variable release;
  bool go = false;
  std::atomic<int> started{0};
  WorkerPool pool(1, 1);
  auto blocker = [&] {
    ++started;
    std::unique_lock<std::mutex> lock(mutex);
    release.wait(lock, [&] { return go; });
  };
  ASSERT_TRUE(pool.TrySubmit(blocker));
  while (started.load() == 0) std::this_thread::yield();  // the worker holds task 1
  EXPECT_TRUE(pool.TrySubmit(blocker));   // waits in the queue
  EXPECT_FALSE(pool.TrySubmit(blocker));  // queue of 1 is full
  {
    std::lock_guard<std::mutex> lock(mutex);
    go = true;
  }
  release.notify_all();
}

}  // namespace
}  // namespace koma::server

#include "platform/thread_task_runner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "core/forward_kinematics.h"
#include "core/split_mix64.h"
#include "tests/testing/long_chain_clip.h"

namespace koma::platform {
namespace {

TEST(ThreadTaskRunnerTest, RunsEachPieceOnceEachOnAThreadOfItsOwn) {
  for (const int count : {0, 1, 2, 5}) {
    std::vector<std::atomic<int>> runs(count);
    std::mutex mutex;
    std::set<std::thread::id> threads;
    ThreadTaskRunner(4).Run(count, [&](int i) {
      runs[i].fetch_add(1);
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    });
    for (int i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << i << " of " << count;
    EXPECT_EQ(static_cast<int>(threads.size()), count);
    if (count > 0) {
      EXPECT_EQ(threads.count(std::this_thread::get_id()), 1u);  // piece 0 ran here
    }
  }
}

TEST(ThreadTaskRunnerTest, ParallelismIsAtLeastOne) {
  EXPECT_EQ(ThreadTaskRunner(0).Parallelism(), 1);
  EXPECT_EQ(ThreadTaskRunner(-3).Parallelism(), 1);
  EXPECT_EQ(ThreadTaskRunner(3).Parallelism(), 3);
}

// Forward kinematics of long clips on real threads (as koma_server runs it with
// --threads_per_call): the same bits as on the calling thread alone.
TEST(ThreadTaskRunnerTest, ForwardKinematicsOnThreadsGivesTheSameBits) {
  SplitMix64 rng(41);
  const Skeleton skeleton = testing::FiveJointChain();
  const int frames = kFramesPerFkThread * 3 + 5;
  const std::vector<double> values = testing::RandomChannelValues(skeleton, frames, rng);
  absl::StatusOr<LargeArray<double>> one = ComputeWorldPositions(skeleton, values, frames);
  ASSERT_TRUE(one.ok()) << one.status();
  for (const int threads : {2, 3, 7}) {
    absl::StatusOr<LargeArray<double>> many =
        ComputeWorldPositions(skeleton, values, frames, ThreadTaskRunner(threads));
    ASSERT_TRUE(many.ok()) << many.status();
    ASSERT_EQ(many->size(), one->size());
    EXPECT_EQ(std::memcmp(many->data(), one->data(), sizeof(double) * one->size()), 0)
        << threads << " threads";
  }
}

}  // namespace
}  // namespace koma::platform

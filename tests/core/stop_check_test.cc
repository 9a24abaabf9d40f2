// StopPoll and the stop signal (core/stop_check.h), and the core loops that poll it: a loop
// whose input grows must stop soon after the signal says so, and say nothing without one.
#include "core/stop_check.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>

#include "core/forward_kinematics.h"
#include "core/split_mix64.h"
#include "tests/testing/long_chain_clip.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;

// Says stop once it has been asked `ok_answers` times; counts the questions.
class CountingSignal final : public StopSignal {
 public:
  explicit CountingSignal(int ok_answers) : ok_answers_(ok_answers) {}
  absl::Status Reason() const override {
    if (asked_.fetch_add(1) < ok_answers_) return absl::OkStatus();
    return absl::DeadlineExceededError("test deadline");
  }
  int asked() const { return asked_.load(); }

 private:
  int ok_answers_;
  mutable std::atomic<int> asked_{0};
};

TEST(StopCheckTest, WithoutASignalNothingStops) {
  StopPoll poll(/*steps_between_checks=*/2);
  for (int i = 0; i < 1000; ++i) ASSERT_FALSE(poll.Stop());
  EXPECT_THAT(poll.status(), IsOk());
  EXPECT_THAT(StopReason(), IsOk());
}

TEST(StopCheckTest, AsksOnceEveryStepsBetweenChecksAndStaysStopped) {
  const CountingSignal signal(/*ok_answers=*/3);
  const StopSignalScope scope(&signal);
  StopPoll poll(/*steps_between_checks=*/10);
  int steps = 0;
  while (!poll.Stop()) ++steps;
  // Asked at steps 10, 20, 30 (OK) and 40 (stop): 39 steps went on.
  EXPECT_EQ(steps, 39);
  EXPECT_EQ(signal.asked(), 4);
  EXPECT_THAT(poll.status(), StatusIs(absl::StatusCode::kDeadlineExceeded, HasSubstr("test")));
  EXPECT_TRUE(poll.Stop());
  EXPECT_TRUE(poll.Stop(100));
  EXPECT_EQ(signal.asked(), 4);  // stopped for good: not asked again
}

TEST(StopCheckTest, LargeStepsCountAsMany) {
  const CountingSignal signal(/*ok_answers=*/0);
  const StopSignalScope scope(&signal);
  StopPoll poll(/*steps_between_checks=*/1000);
  EXPECT_FALSE(poll.Stop(999));
  EXPECT_TRUE(poll.Stop(1));
}

TEST(StopCheckTest, ScopesNestAndRestore) {
  const CountingSignal outer(/*ok_answers=*/1000);
  const CountingSignal inner(/*ok_answers=*/0);
  const StopSignalScope outer_scope(&outer);
  {
    const StopSignalScope inner_scope(&inner);
    EXPECT_THAT(StopReason(), StatusIs(absl::StatusCode::kDeadlineExceeded, ::testing::_));
  }
  EXPECT_THAT(StopReason(), IsOk());
}

TEST(StopCheckTest, ForwardKinematicsReturnsTheStopInsteadOfUnfinishedPositions) {
  const Skeleton skeleton = testing::FiveJointChain();
  SplitMix64 rng(7);
  const std::vector<double> values = testing::RandomChannelValues(skeleton, 100'000, rng);
  {
    SkeletalClip clip;
    clip.skeleton = skeleton;
    clip.frame_count = 100'000;
    clip.values = values;
    const CountingSignal signal(/*ok_answers=*/2);
    const StopSignalScope scope(&signal);
    EXPECT_THAT(ComputeWorldPositions(clip).status(),
                StatusIs(absl::StatusCode::kDeadlineExceeded, ::testing::_));
    // Asked every ~65,536 joint transforms, not once a frame: 100,000 frames x 5 joints.
    EXPECT_LE(signal.asked(), 10);
  }
}

}  // namespace
}  // namespace koma

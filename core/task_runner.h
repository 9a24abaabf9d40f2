// How an algorithm spreads independent pieces of work over threads without starting any.
//
// core starts no threads: an algorithm that can split its work (forward kinematics of a long
// clip) takes a TaskRunner from the caller and asks it to run the pieces. koma_server passes
// one that runs them on threads (platform/thread_task_runner.h); without one, or with
// InlineTaskRunner, the pieces run one after another on the calling thread. The pieces never
// depend on each other, so the result is the same, bit for bit, either way.
#ifndef KOMA_CORE_TASK_RUNNER_H_
#define KOMA_CORE_TASK_RUNNER_H_

#include "absl/functional/function_ref.h"

namespace koma {

class TaskRunner {
 public:
  virtual ~TaskRunner() = default;
  // How many pieces are worth making: the threads this runner may use, at least 1.
  virtual int Parallelism() const = 0;
  // Runs task(0) ... task(count - 1), each exactly once, possibly at the same time; returns
  // when all have returned.
  virtual void Run(int count, absl::FunctionRef<void(int)> task) const = 0;
};

// Runs every piece on the calling thread, in order.
class InlineTaskRunner final : public TaskRunner {
 public:
  int Parallelism() const override { return 1; }
  void Run(int count, absl::FunctionRef<void(int)> task) const override {
    for (int i = 0; i < count; ++i) task(i);
  }
};

}  // namespace koma

#endif  // KOMA_CORE_TASK_RUNNER_H_

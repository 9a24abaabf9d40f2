// A TaskRunner (core/task_runner.h) that runs the pieces on threads of their own: koma_server
// gives it to forward kinematics for long clips (--threads_per_call).
#ifndef KOMA_PLATFORM_THREAD_TASK_RUNNER_H_
#define KOMA_PLATFORM_THREAD_TASK_RUNNER_H_

#include "core/task_runner.h"

namespace koma::platform {

class ThreadTaskRunner final : public TaskRunner {
 public:
  // Up to `threads` threads (values below 1 count as 1): the calling thread runs the first
  // piece and a fresh thread each other one, so a call's pieces never wait for another call's.
  explicit ThreadTaskRunner(int threads) : threads_(threads < 1 ? 1 : threads) {}

  int Parallelism() const override { return threads_; }
  void Run(int count, absl::FunctionRef<void(int)> task) const override;

 private:
  int threads_;
};

}  // namespace koma::platform

#endif  // KOMA_PLATFORM_THREAD_TASK_RUNNER_H_

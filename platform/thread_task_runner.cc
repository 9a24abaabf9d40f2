#include "platform/thread_task_runner.h"

#include <thread>
#include <vector>

namespace koma::platform {

void ThreadTaskRunner::Run(int count, absl::FunctionRef<void(int)> task) const {
  std::vector<std::thread> helpers;
  helpers.reserve(count > 1 ? count - 1 : 0);
  for (int i = 1; i < count; ++i) helpers.emplace_back([task, i] { task(i); });
  if (count > 0) task(0);
  for (std::thread& helper : helpers) helper.join();
}

}  // namespace koma::platform

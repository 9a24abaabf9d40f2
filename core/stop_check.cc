#include "core/stop_check.h"

namespace koma {
namespace {

thread_local const StopSignal* installed_signal = nullptr;

}  // namespace

StopSignalScope::StopSignalScope(const StopSignal* signal) : previous_(installed_signal) {
  installed_signal = signal;
}

StopSignalScope::~StopSignalScope() { installed_signal = previous_; }

absl::Status StopReason() {
  const StopSignal* signal = installed_signal;
  return signal == nullptr ? absl::OkStatus() : signal->Reason();
}

bool StopPoll::Check() {
  if (stopped_) return true;
  status_ = StopReason();
  stopped_ = !status_.ok();
  return stopped_;
}

}  // namespace koma

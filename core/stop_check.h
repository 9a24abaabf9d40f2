// Stopping long work early: a program (koma_server, per call) installs a StopSignal on the
// thread that runs a computation, and every loop whose length the input controls (decoding,
// analysis, evaluation, writing) polls it through a StopPoll every few thousand steps. The
// server's signal says stop when the call's deadline passes, the client cancels, the call has
// run --max_call_seconds or the server is shutting down (server/call_stop.h).
//
// A loop that sees the signal either returns its status (a function that returns a Status) or
// breaks out, leaving its outputs sized but unfinished; the program that installed the signal
// asks it again once the computation returns and discards such a result. Without a signal
// installed (the CLI, tests, benchmarks) polling costs a counter and never stops anything.
#ifndef KOMA_CORE_STOP_CHECK_H_
#define KOMA_CORE_STOP_CHECK_H_

#include <cstdint>

#include "absl/status/status.h"

namespace koma {

class StopSignal {
 public:
  virtual ~StopSignal() = default;
  // OK to go on; else why to stop (DEADLINE_EXCEEDED, CANCELLED, ...). Called from the
  // computing thread every few milliseconds at most; must be cheap and thread-safe.
  virtual absl::Status Reason() const = 0;
};

// While alive, StopPoll on this thread asks `signal` (which must outlive the scope).
class StopSignalScope {
 public:
  explicit StopSignalScope(const StopSignal* signal);
  ~StopSignalScope();
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;

 private:
  const StopSignal* previous_;
};

// The installed signal's reason, OK when none is installed.
absl::Status StopReason();

// Asks the installed signal once every `steps_between_checks` steps (Tick's `steps` add up),
// so a loop of cheap steps pays a counter per step. Once it has said stop it stays stopped.
class StopPoll {
 public:
  // The default suits steps of about a microsecond or less (a sample, a key, a frame of a
  // few values): a check every ~1 ms of work.
  explicit StopPoll(int64_t steps_between_checks = 4096)
      : between_(steps_between_checks), left_(steps_between_checks) {}

  // True when the work should stop (and from then on).
  bool Stop(int64_t steps = 1) {
    left_ -= steps;
    if (left_ > 0) return stopped_;
    left_ = between_;
    return Check();
  }
  // Why it stopped (OK while it has not).
  const absl::Status& status() const { return status_; }

 private:
  bool Check();

  int64_t between_;
  int64_t left_;
  bool stopped_ = false;
  absl::Status status_;
};

}  // namespace koma

#endif  // KOMA_CORE_STOP_CHECK_H_

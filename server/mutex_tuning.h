// Abseil's mutex deadlock detection, off. Debian's Abseil is built without NDEBUG, so every
// absl::Mutex (gRPC's own locks are absl::Mutex) records which locks are held together in a
// global graph, a debugging aid: in a perf profile of koma_server under Pitch-size load
// (perf, 20,000 calls at c = 4, 2026-11-22) GraphCycles alone took 1.4 % of the CPU, and
// the mutex library 1.2 % where it takes 0.75 % without. koma_server calls this first thing in
// main(); so does koma_echo_server, so the transport baseline saves the same.
#ifndef KOMA_SERVER_MUTEX_TUNING_H_
#define KOMA_SERVER_MUTEX_TUNING_H_

#include "absl/synchronization/mutex.h"

namespace koma::server {

inline void IgnoreMutexDeadlockCycles() {
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
}

}  // namespace koma::server

#endif  // KOMA_SERVER_MUTEX_TUNING_H_

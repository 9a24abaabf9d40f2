// The memory-budget reservation of the call running on this thread, for handlers that learn a
// call's size only on the way: a request carrying a file (server/file_requests.h) is sized by
// its text until the file is parsed, and by what it decodes to after that.
//
// The service sets the scope around a call's handler (retime_service.cc, ArenaBytesCall::Run);
// a handler runs on one thread from start to end (gRPC's callback thread or a worker), so a
// thread-local pointer names its call's reservation without changing the handlers' signature.
#ifndef KOMA_SERVER_CALL_RESERVATION_H_
#define KOMA_SERVER_CALL_RESERVATION_H_

#include <cstdint>

#include "absl/status/status.h"
#include "server/memory_budget.h"

namespace koma::server {

// While alive, GrowCallReservation on this thread grows `reservation`.
class CallReservationScope {
 public:
  explicit CallReservationScope(MemoryBudget::Reservation* reservation);
  ~CallReservationScope();
  CallReservationScope(const CallReservationScope&) = delete;
  CallReservationScope& operator=(const CallReservationScope&) = delete;

 private:
  MemoryBudget::Reservation* previous_;
};

// Grows the running call's reservation to `bytes` when it holds less; RESOURCE_EXHAUSTED naming
// the budget and `what` when that does not fit. OK without a scope or a budget.
absl::Status GrowCallReservation(int64_t bytes, const char* what);

}  // namespace koma::server

#endif  // KOMA_SERVER_CALL_RESERVATION_H_

#include "server/call_reservation.h"

namespace koma::server {
namespace {

thread_local MemoryBudget::Reservation* current_reservation = nullptr;

}  // namespace

CallReservationScope::CallReservationScope(MemoryBudget::Reservation* reservation)
    : previous_(current_reservation) {
  current_reservation = reservation;
}

CallReservationScope::~CallReservationScope() { current_reservation = previous_; }

absl::Status GrowCallReservation(int64_t bytes, const char* what) {
  MemoryBudget::Reservation* reservation = current_reservation;
  if (reservation == nullptr || !reservation->budgeted() || bytes <= reservation->bytes()) {
    return absl::OkStatus();
  }
  return reservation->Resize(bytes, what);
}

}  // namespace koma::server

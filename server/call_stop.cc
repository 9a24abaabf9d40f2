#include "server/call_stop.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace koma::server {
namespace {

long long MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                               start)
      .count();
}

}  // namespace

CallStopSignal::CallStopSignal(const grpc::ServerContextBase* context,
                               std::chrono::steady_clock::time_point start, double max_call_seconds)
    : context_(context),
      start_(start),
      client_deadline_(context->deadline()),
      server_deadline_(max_call_seconds > 0
                           ? start +
                                 std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(max_call_seconds))
                           : std::chrono::steady_clock::time_point::max()),
      max_call_seconds_(max_call_seconds) {}

absl::Status CallStopSignal::Reason() const {
  // The deadline first: gRPC also marks a call whose deadline passed as cancelled, and the
  // log should name the deadline.
  if (std::chrono::system_clock::now() > client_deadline_) {
    return absl::DeadlineExceededError(absl::StrCat(
        "the client's deadline passed after ", MillisecondsSince(start_), " ms; the work stopped"));
  }
  if (std::chrono::steady_clock::now() > server_deadline_) {
    return absl::DeadlineExceededError(absl::StrCat(
        "the call ran longer than the server limit --max_call_seconds=", max_call_seconds_,
        "; the work stopped (send a smaller request, or raise the limit)"));
  }
  if (context_->IsCancelled()) {
    return absl::CancelledError(absl::StrCat("the call was cancelled after ",
                                             MillisecondsSince(start_),
                                             " ms (its client went away, or the server is "
                                             "shutting down); the work stopped"));
  }
  return absl::OkStatus();
}

}  // namespace koma::server

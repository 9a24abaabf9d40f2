// Early-return helpers for absl::Status / absl::StatusOr. Debian's abseil (20220623) ships
// neither absl/status/status_macros.h nor matchers, so koma defines its own.
#ifndef KOMA_CORE_STATUS_MACROS_H_
#define KOMA_CORE_STATUS_MACROS_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"

#define KOMA_STATUS_CONCAT_INNER_(a, b) a##b
#define KOMA_STATUS_CONCAT_(a, b) KOMA_STATUS_CONCAT_INNER_(a, b)

// Returns the status from the enclosing function if `expr` is not OK.
#define KOMA_RETURN_IF_ERROR(expr)                    \
  do {                                                \
    const ::absl::Status koma_status_ = (expr);       \
    if (!koma_status_.ok()) return koma_status_;      \
  } while (false)

// `KOMA_ASSIGN_OR_RETURN(auto x, MakeX());` declares/assigns `x` from a StatusOr, or
// returns its status from the enclosing function.
#define KOMA_ASSIGN_OR_RETURN(lhs, expr)                                          \
  KOMA_ASSIGN_OR_RETURN_IMPL_(KOMA_STATUS_CONCAT_(koma_statusor_, __LINE__), lhs, \
                              expr)
#define KOMA_ASSIGN_OR_RETURN_IMPL_(statusor, lhs, expr) \
  auto statusor = (expr);                                \
  if (!statusor.ok()) return std::move(statusor).status(); \
  lhs = std::move(statusor).value()

#endif  // KOMA_CORE_STATUS_MACROS_H_

// Errors about a koma.v1 request field: a check's message with the field's path in front, so
// a client reads which field and value were refused ("mouth.frames_per_shape: 0 must be
// >= 1"). The server's request validation and convert/'s proto -> core conversion use it.
#ifndef KOMA_CONVERT_FIELD_ERROR_H_
#define KOMA_CONVERT_FIELD_ERROR_H_

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"

namespace koma::convert {

// `status` with `prefix` before its message (same code); OK stays OK.
inline absl::Status Prefixed(const absl::Status& status, absl::string_view prefix) {
  if (status.ok()) return status;
  return absl::Status(status.code(), absl::StrCat(prefix, status.message()));
}

}  // namespace koma::convert

#endif  // KOMA_CONVERT_FIELD_ERROR_H_

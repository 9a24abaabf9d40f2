// Whole-file reads and writes for the CLI.
#ifndef KOMA_CLIENT_FILES_H_
#define KOMA_CLIENT_FILES_H_

#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::client {

// NOT_FOUND / PERMISSION_DENIED / ... naming the path and the OS error.
absl::StatusOr<std::string> ReadFile(const std::string& path);
// Writes through "<path>.tmp" and a rename, so a failed run never leaves half a file.
absl::Status WriteFile(const std::string& path, const std::string& contents);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILES_H_

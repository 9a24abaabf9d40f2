// Whole-file reads and writes for the CLI.
#ifndef KOMA_CLIENT_FILES_H_
#define KOMA_CLIENT_FILES_H_

#include <initializer_list>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::client {

// NOT_FOUND / PERMISSION_DENIED / ... naming the path and the OS error.
absl::StatusOr<std::string> ReadFile(const std::string& path);
// Writes through "<path>.tmp" and a rename, so a failed run never leaves half a file.
absl::Status WriteFile(const std::string& path, const std::string& contents);
// Before a call: each non-empty path could be written (its folder exists and takes new files,
// and it is not itself a folder), so an answer is not computed, perhaps for minutes, only to
// be lost, or half of a run's outputs written. Errors as WriteFile's, naming the path.
absl::Status CheckWritable(std::initializer_list<std::string> paths);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILES_H_

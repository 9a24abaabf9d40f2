// Whole-file reads and writes for the CLI. The name "-" is standard input (reads) or standard
// output (writes) everywhere a path is taken.
#ifndef KOMA_CLIENT_FILES_H_
#define KOMA_CLIENT_FILES_H_

#include <initializer_list>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::client {

// True for "-": standard input or output.
bool IsStdio(const std::string& path);

// How messages, summaries and reports name a path: "standard input" (InputName, a path read)
// or "standard output" (OutputName, a path written) for "-", else the path itself.
std::string InputName(std::string_view path);
std::string OutputName(std::string_view path);

// An output flag and its path ({"-o", args.output}).
struct OutputFlag {
  const char* flag;
  const std::string& path;
};

// INVALID_ARGUMENT when more than one of `outputs` is "-" (with --json, `json`, counted as
// one more): "only one of -o -, --report - and --json can use standard output", naming the
// flags given.
absl::Status CheckOneOnStdout(std::initializer_list<OutputFlag> outputs, bool json);

// The whole file ("-": all of standard input). NOT_FOUND / PERMISSION_DENIED / ... naming
// the path and the OS error ("cannot read x.bvh: No such file or directory").
absl::StatusOr<std::string> ReadFile(const std::string& path);

// Writes `contents` as the whole of `path`, so a failed run never leaves half a file:
// - "-": to standard output.
// - A symbolic link is followed (links to links too) and its final target written; the link
//   itself is never replaced.
// - A target that exists and is not a regular file (a device such as /dev/null, a named pipe)
//   is opened and written directly.
// - Otherwise through a temporary file in the target's folder, flushed to disk and renamed
//   over the target: the target keeps its permission bits (a new one gets 0666 less umask).
// Errors name the path and the OS error.
absl::Status WriteFile(const std::string& path, const std::string& contents);

// The file WriteFile(path) writes: `path` with every symbolic link in its last component
// followed (relative links resolved against the link's folder); `path` itself when it is not
// a link. FAILED_PRECONDITION for a loop of more than 40 links.
absl::StatusOr<std::string> ResolveOutputPath(const std::string& path);

// Before a call: each non-empty path could be written (its folder exists and takes new files,
// it is not itself a folder; a device or pipe is writable; "-" always), so an answer is not
// computed, perhaps for minutes, only to be lost, or half of a run's outputs written. Errors
// as WriteFile's, naming the path.
absl::Status CheckWritable(std::initializer_list<std::string> paths);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILES_H_

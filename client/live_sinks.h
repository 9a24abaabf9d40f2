// The sinks of `koma live` (client/live_sink.h) its flags ask for, and the flags of the sinks
// that are not the command's own (the avatar links). A new sink: its flags in
// AddLiveSinkFlags, its LiveArgs field, and one branch in MakeLiveSinks.
#ifndef KOMA_CLIENT_LIVE_SINKS_H_
#define KOMA_CLIENT_LIVE_SINKS_H_

#include <CLI/CLI.hpp>
#include <memory>
#include <vector>

#include "absl/status/statusor.h"
#include "client/live_command.h"
#include "client/live_sink.h"

namespace koma::client {

// The avatar links' flags (--vmc, --vts), on `koma live`.
void AddLiveSinkFlags(CLI::App* cmd, LiveArgs& args);

// In order: the --json lines (or the human lines), --record, the avatar links. Errors (an
// unwritable --record folder, a link that cannot be set up) name the flag.
absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> MakeLiveSinks(const LiveArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_SINKS_H_

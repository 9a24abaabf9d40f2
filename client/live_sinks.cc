#include "client/live_sinks.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "client/files.h"
#include "client/live_output.h"
#include "client/live_record.h"

namespace koma::client {

void AddLiveSinkFlags(CLI::App* cmd, LiveArgs& args) {
  AddAvatarSinkFlags(*cmd, args.avatar);  // --vmc [HOST:PORT], --vts [URL] and their names
}

absl::StatusOr<std::vector<std::unique_ptr<LiveSink>>> MakeLiveSinks(const LiveArgs& args) {
  std::vector<std::unique_ptr<LiveSink>> sinks;
  if (args.json) sinks.push_back(NewLiveJsonSink(stdout));
  if (!args.quiet) sinks.push_back(NewLiveTextSink(LiveTextStream(args)));
  if (!args.record.empty()) {
    if (absl::Status s = CheckWritable({args.record}); !s.ok()) {
      return absl::Status(s.code(), absl::StrCat("--record: ", s.message()));
    }
    sinks.push_back(NewLiveRecordSink(args.record));
  }
  if (absl::Status s = AddAvatarSinks(args.avatar, sinks); !s.ok()) return s;
  return sinks;
}

}  // namespace koma::client

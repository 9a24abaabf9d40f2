// The flags of every `koma` command that calls the server (--server, --deadline, --json,
// --quiet), one struct that each command's arguments extend; registered on a command by
// AddCommonFlags (client/command_flags.h).
#ifndef KOMA_CLIENT_CALL_FLAGS_H_
#define KOMA_CLIENT_CALL_FLAGS_H_

#include <string>

namespace koma::client {

struct CallFlags {
  std::string server;              // --server host:port, or a list (client/channel.h)
  double deadline_seconds = 60.0;  // --deadline, seconds
  bool json = false;               // --json: the summary as one JSON object on stdout
  bool quiet = false;              // --quiet: no human summary
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_CALL_FLAGS_H_

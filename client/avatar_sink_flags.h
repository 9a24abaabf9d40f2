// The avatar links of `koma live`: --vmc (client/vmc_sink.h) and --vts
// (client/vtube_studio_sink.h), their flags registered on the command in one call and made
// into sinks in another, so the command needs two lines for them.
#ifndef KOMA_CLIENT_AVATAR_SINK_FLAGS_H_
#define KOMA_CLIENT_AVATAR_SINK_FLAGS_H_

#include <memory>
#include <string>
#include <vector>

#include "CLI/CLI.hpp"
#include "absl/status/status.h"
#include "client/live_sink.h"
#include "client/vmc_sink.h"
#include "client/vtube_studio_sink.h"

namespace koma::client {

struct AvatarSinkFlags {
  CLI::Option* vmc = nullptr;  // given (with or without a value) when count() > 0
  std::string vmc_target;      // "" = kVmcDefaultTarget
  VmcOptions vmc_options;
  CLI::Option* vts = nullptr;
  std::string vts_url;  // "" = kVtsDefaultUrl
  VtsOptions vts_options;
};

// --vmc [HOST:PORT], --vmc-mouth-clip, --vmc-blink-clip, --vts [URL], --vts-token-file,
// --vts-mouth-param, --vts-eye-left-param, --vts-eye-right-param (docs/live.md).
void AddAvatarSinkFlags(CLI::App& command, AvatarSinkFlags& flags);

// Appends the sinks the flags ask for. INVALID_ARGUMENT for a bad --vmc target, an empty clip
// or parameter name.
absl::Status AddAvatarSinks(const AvatarSinkFlags& flags,
                            std::vector<std::unique_ptr<LiveSink>>& sinks);

}  // namespace koma::client

#endif  // KOMA_CLIENT_AVATAR_SINK_FLAGS_H_

#include "client/avatar_sink_flags.h"

#include <utility>

#include "absl/strings/str_cat.h"

namespace koma::client {

void AddAvatarSinkFlags(CLI::App& command, AvatarSinkFlags& flags) {
  flags.vmc = command
                  .add_option("--vmc", flags.vmc_target,
                              "Send each frame as VMC (OSC over UDP) blend shapes to HOST:PORT "
                              "(VSeeFace, VMagicMirror, Warudo, VNyan); default 127.0.0.1:39539")
                  ->expected(0, 1)
                  ->type_name("[HOST:PORT]");
  command.add_option("--vmc-mouth-clip", flags.vmc_options.mouth_clip,
                     "VRM blend shape clip of the open mouth (VRM 1.0: aa)")
      ->capture_default_str();
  command.add_option("--vmc-blink-clip", flags.vmc_options.blink_clip,
                     "VRM blend shape clip of the closed eyes (VRM 1.0: blink)")
      ->capture_default_str();
  flags.vts = command
                  .add_option("--vts", flags.vts_url,
                              "Inject each frame into VTube Studio's plugin API at URL; default "
                              "ws://localhost:8001")
                  ->expected(0, 1)
                  ->type_name("[URL]");
  command.add_option("--vts-token-file", flags.vts_options.token_file,
                     "Where VTube Studio's plugin token is kept (default "
                     "$XDG_CONFIG_HOME/koma/vts-token)");
  command.add_option("--vts-mouth-param", flags.vts_options.mouth_parameter,
                     "VTube Studio input parameter of the mouth (0 closed .. 1 open)")
      ->capture_default_str();
  command.add_option("--vts-eye-left-param", flags.vts_options.eye_left_parameter,
                     "VTube Studio input parameter of the left eye (0 shut .. 1 open)")
      ->capture_default_str();
  command.add_option("--vts-eye-right-param", flags.vts_options.eye_right_parameter,
                     "VTube Studio input parameter of the right eye (0 shut .. 1 open)")
      ->capture_default_str();
}

absl::Status AddAvatarSinks(AvatarSinkFlags& flags,
                            std::vector<std::unique_ptr<LiveSink>>& sinks) {
  for (const auto& [flag, name] :
       {std::pair<const char*, const std::string&>{"--vmc-mouth-clip",
                                                    flags.vmc_options.mouth_clip},
        {"--vmc-blink-clip", flags.vmc_options.blink_clip},
        {"--vts-mouth-param", flags.vts_options.mouth_parameter},
        {"--vts-eye-left-param", flags.vts_options.eye_left_parameter},
        {"--vts-eye-right-param", flags.vts_options.eye_right_parameter}}) {
    if (name.empty()) return absl::InvalidArgumentError(absl::StrCat(flag, " must not be empty"));
  }
  if (flags.vmc != nullptr && flags.vmc->count() > 0) {
    if (absl::Status parsed = ParseVmcTarget(flags.vmc_target, "--vmc", flags.vmc_options);
        !parsed.ok()) {
      return parsed;
    }
    absl::StatusOr<std::unique_ptr<VmcSink>> sink = VmcSink::Open(flags.vmc_options);
    if (!sink.ok()) return sink.status();
    sinks.push_back(std::move(*sink));
  }
  if (flags.vts != nullptr && flags.vts->count() > 0) {
    VtsOptions options = flags.vts_options;
    options.url = flags.vts_url.empty() ? kVtsDefaultUrl : flags.vts_url;
    // The URL is checked now, a usage error, rather than when the stream starts.
    if (absl::StatusOr<WebSocketUrl> url = ParseWebSocketUrl(options.url); !url.ok()) {
      return absl::InvalidArgumentError(absl::StrCat("--vts: ", url.status().message()));
    }
    sinks.push_back(std::make_unique<VtubeStudioSink>(std::move(options)));
  }
  return absl::OkStatus();
}

}  // namespace koma::client

#include "client/avatar_sink_flags.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace koma::client {
namespace {

// CLI11 validators: a bad value is a usage error (exit 2) before anything is opened.
CLI::Validator VmcTargetValidator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        VmcOptions options;
        const absl::Status parsed = ParseVmcTarget(value, "--vmc", options);
        // CLI11 names the flag itself.
        return parsed.ok() ? "" : std::string(absl::StripPrefix(parsed.message(), "--vmc: "));
      },
      "");
}

CLI::Validator VtsUrlValidator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        if (value.empty()) return "";
        const absl::StatusOr<WebSocketUrl> url = ParseWebSocketUrl(value);
        return url.ok() ? "" : std::string(url.status().message());
      },
      "");
}

CLI::Validator NotEmpty() {
  return CLI::Validator(
      [](std::string& value) -> std::string { return value.empty() ? "must not be empty" : ""; },
      "");
}

}  // namespace

void AddAvatarSinkFlags(CLI::App& command, AvatarSinkFlags& flags) {
  flags.vmc = command
                  .add_option("--vmc", flags.vmc_target,
                              "send each frame as VMC blend shapes (OSC over UDP) to VSeeFace, "
                              "VMagicMirror, Warudo or VNyan at HOST:PORT (default "
                              "127.0.0.1:39539)")
                  ->expected(0, 1)
                  ->type_name("[HOST:PORT]")
                  ->check(VmcTargetValidator());
  command.add_option("--vmc-mouth-clip", flags.vmc_options.mouth_clip,
                     "VRM blend shape clip of the open mouth (default A; VRM 1.0: aa)")
      ->type_name("NAME")
      ->check(NotEmpty());
  command.add_option("--vmc-blink-clip", flags.vmc_options.blink_clip,
                     "VRM blend shape clip of the closed eyes (default Blink; VRM 1.0: blink)")
      ->type_name("NAME")
      ->check(NotEmpty());
  flags.vts = command
                  .add_option("--vts", flags.vts_url,
                              "inject each frame into VTube Studio through its plugin API at URL "
                              "(default ws://localhost:8001)")
                  ->expected(0, 1)
                  ->type_name("[URL]")
                  ->check(VtsUrlValidator());
  command.add_option("--vts-token-file", flags.vts_options.token_file,
                     "where the token VTube Studio gave koma is kept (default "
                     "$XDG_CONFIG_HOME/koma/vts-token, or ~/.config/koma/vts-token)")
      ->type_name("FILE");
  command.add_option("--vts-mouth-param", flags.vts_options.mouth_parameter,
                     "VTube Studio input parameter of the mouth, 0 closed .. 1 open (default "
                     "MouthOpen)")
      ->type_name("NAME")
      ->check(NotEmpty());
  command.add_option("--vts-eye-left-param", flags.vts_options.eye_left_parameter,
                     "VTube Studio input parameter of the left eye, 0 shut .. 1 open (default "
                     "EyeOpenLeft)")
      ->type_name("NAME")
      ->check(NotEmpty());
  command.add_option("--vts-eye-right-param", flags.vts_options.eye_right_parameter,
                     "VTube Studio input parameter of the right eye, 0 shut .. 1 open (default "
                     "EyeOpenRight)")
      ->type_name("NAME")
      ->check(NotEmpty());
}

absl::Status AddAvatarSinks(const AvatarSinkFlags& flags,
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
    VmcOptions options = flags.vmc_options;
    if (absl::Status parsed = ParseVmcTarget(flags.vmc_target, "--vmc", options); !parsed.ok()) {
      return parsed;
    }
    absl::StatusOr<std::unique_ptr<VmcSink>> sink = VmcSink::Open(options);
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

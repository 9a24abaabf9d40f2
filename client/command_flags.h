// The flags of each `koma` subcommand, registered on a CLI11 app. Request fields are named as
// in koma.v1 in kebab-case (omissions -> --omissions, mouth.mid_ratio -> --mouth-mid-ratio,
// eyes.auto_blink.spread_s -> --auto-blink-spread-s), with the short names of earlier
// versions kept as aliases (--omit, --hold, --on, --keys, ...). docs/usage.md lists them all.
#ifndef KOMA_CLIENT_COMMAND_FLAGS_H_
#define KOMA_CLIENT_COMMAND_FLAGS_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "client/call_flags.h"
#include "client/channel.h"
#include "client/curve_files.h"
#include "client/curves_command.h"
#include "client/health_command.h"
#include "client/lip_blink_command.h"
#include "client/skeletal_command.h"

namespace koma::client {

// --preset NAME of skeletal, curves and lipblink: common settings as flags (twos, threes,
// snappy, subtle, paper; the table in docs/usage.md, "Presets and studio defaults").
const std::vector<std::string>& PresetNames();
// The flags of preset `name` for `command`; nullptr for an unknown name.
const std::vector<std::string>* PresetFlags(const std::string& command, const std::string& name);
// Registers --preset on `cmd` (for --help and the unknown-option check; the command line
// parser expands it before CLI11 sees it).
void AddPresetFlag(CLI::App* cmd);

// --server, --deadline (seconds), --json, --quiet: on every subcommand.
void AddCommonFlags(CLI::App* cmd, CallFlags* flags, const std::string& default_deadline);

// --tls-ca, --tls-cert, --tls-key (also $KOMA_TLS_*): on `koma` and on `koma batch`.
void AddTlsFlags(CLI::App& app, TlsFiles& tls);

// The flags the file commands share, each registered where the command's help lists it.
// The input file of curves and lipblink (motion3.json or CSV).
void AddCurveInputFlag(CLI::App* cmd, std::string* input);
// --report OUT.html.
void AddReportFlag(CLI::App* cmd, std::string* report);
// --xdts OUT.xdts.
void AddXdtsFlag(CLI::App* cmd, std::string* xdts);
// --timing-fps: "film grid `counted` counted on ... 0 = count in `frames_of` own frames".
void AddTimingFpsFlag(CLI::App* cmd, std::optional<double>* timing_fps, const std::string& counted,
                      const std::string& frames_of);
// --send-file: the file goes in the request's `fields` for the server to parse.
void AddSendFileFlag(CLI::App* cmd, bool* send_file, const std::string& fields);
// The last flags of curves and lipblink: --fps, --timing-fps (see AddTimingFpsFlag),
// --format, --send-file, --preset and the common flags.
void AddCurveFileFlags(CLI::App* cmd, CurveFileArgs& args, const std::string& timing_counted);

// Each adds its subcommand to `app` with every flag bound to `args`, and returns it.
CLI::App* AddSkeletalCommand(CLI::App& app, SkeletalArgs& args);
CLI::App* AddCurvesCommand(CLI::App& app, CurvesArgs& args);
CLI::App* AddLipBlinkCommand(CLI::App& app, LipBlinkArgs& args);
// The --voice-settings-* flags (LipBlinkVoiceSettings) into `args`, for koma lipblink and koma
// live; the three helps that differ between a recording and a live stream are given.
struct VoiceSettingsHelp {
  const char* noise_floor;
  const char* noise_percentile;
  const char* stay_above_floor;
};
void AddVoiceSettingsFlags(CLI::App* cmd, LipBlinkArgs& args, const VoiceSettingsHelp& help);
CLI::App* AddHealthCommand(CLI::App& app, HealthArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_COMMAND_FLAGS_H_

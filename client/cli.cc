#include "client/cli.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <set>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/cli_options.h"
#include "client/command_io.h"
#include "client/command_flags.h"
#include "client/command_output.h"
#include "client/config_file.h"
#include "client/flag_values.h"
#include "koma/version.h"

namespace koma::client {
namespace {

constexpr const char* kGlossary =
    "Terms: koma-uchi, drawings held 1 ('on ones'), 2 ('on twos') or 3 frames ('on threes'); "
    "nakanashi (inbetween omission, --omit), removing the fastest inbetween frames; koma-dori "
    "(holds, --hold), repeating a frame where the motion is stillest; genga, the key poses; "
    "tame, a slow start out of a key; tsume, a slow arrival into the next key; the film grid "
    "(--timing-fps), the 24 fps grid drawings are counted on. Exit codes: 0 ok, 1 failure "
    "(RPC error, unreadable or malformed file), 2 usage error. Full reference: docs/usage.md.\n";

// Options of the top-level app that take a value (and so consume the next argument).
const std::set<std::string>& GlobalValueOptions() {
  static const std::set<std::string> names{"--tls-ca", "--tls-cert", "--tls-key", "--config"};
  return names;
}

void AddGlobalOptions(CLI::App& app, TlsFiles& tls) {
  AddTlsFlags(app, tls);
  // Studio defaults: a TOML file with a [COMMAND] section of option = value lines (names as
  // the long flags without "--"); flags on the command line win.
  app.set_config("--config", "",
                 "TOML file of defaults, e.g. [skeletal] omissions = 6 / server = \"host:50051\"; "
                 "command-line flags win (also $KOMA_CONFIG)")
      ->type_name("FILE");
  app.config_formatter(std::make_shared<ConfigToml>());
  app.set_version_flag("--version", std::string("koma ") + kVersion,
                       "print the version (koma MAJOR.MINOR.PATCH) and exit");
}

// koma's checks before CLI11's: a missing or unknown command, an unknown option. Returns -1
// when the line may go to CLI11, else the exit code (after printing). `command` gets the
// command named.
int PreCheck(const CLI::App& app, const std::vector<std::string>& args, std::string* command,
             size_t* command_index) {
  const std::vector<std::string> global = LongNames(&app);
  size_t i = 1;
  for (; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h" || arg == "--help" || arg == "--version") return -1;
    if (absl::StartsWith(arg, "--")) {
      const std::string name = arg.substr(0, arg.find('='));
      if (GlobalValueOptions().count(name) && name == arg) {
        ++i;
        continue;
      }
      if (std::find(global.begin(), global.end(), name) != global.end()) continue;
      // The command named later on the line if it has the option, else the first that has.
      std::vector<const CLI::App*> subs = app.get_subcommands({});
      for (size_t k = i + 1; k < args.size(); ++k) {
        const auto named = std::find(CommandNames().begin(), CommandNames().end(), args[k]);
        if (named == CommandNames().end()) continue;
        subs.insert(subs.begin(), app.get_subcommand(*named));
        break;
      }
      for (const CLI::App* sub : subs) {
        const std::vector<std::string> names = LongNames(sub);
        if (std::find(names.begin(), names.end(), name) != names.end()) {
          return PrintUsageError("koma",
                                 absl::StrCat(name, " is an option of `koma ", sub->get_name(),
                                              "`: put it after the command (koma ", sub->get_name(),
                                              " ... ", name, ")"),
                                 "koma --help");
        }
      }
      return PrintUsageError(
          "koma", absl::StrCat("unknown option ", name, DidYouMean(name, global)), "koma --help");
    }
    if (absl::StartsWith(arg, "-") && arg.size() > 1) continue;  // CLI11 names it
    break;
  }
  if (i >= args.size()) {
    return PrintUsageError(
        "koma", absl::StrCat("a command is required: ", absl::StrJoin(CommandNames(), ", ")),
        "koma --help");
  }
  const std::string& typed = args[i];
  if (std::find(CommandNames().begin(), CommandNames().end(), typed) == CommandNames().end()) {
    const std::string close = ClosestMatch(typed, CommandNames());
    return PrintUsageError(
        "koma",
        absl::StrCat("unknown command \"", typed, "\"",
                     close.empty() ? "" : absl::StrCat("; did you mean \"", close, "\"?"),
                     close.empty()
                         ? absl::StrCat(" (commands: ", absl::StrJoin(CommandNames(), ", "), ")")
                         : ""),
        "koma --help");
  }
  *command = typed;
  *command_index = i;
  if (const std::string config = ConfigFilePath(args); !config.empty()) {
    if (int code = CheckConfigFile(app, app, config, "koma"); code >= 0) return code;
  }
  const CLI::App* sub = app.get_subcommand(typed);
  std::vector<std::string> known = LongNames(sub);
  known.insert(known.end(), global.begin(), global.end());
  const std::string who = "koma " + typed;
  for (size_t j = i + 1; j < args.size(); ++j) {
    const std::string& arg = args[j];
    if (arg == "--") break;
    const bool is_short = arg.size() == 2 && arg[0] == '-' && arg[1] != '-';
    if (!absl::StartsWith(arg, "--") && !is_short) continue;
    const std::string name = arg.substr(0, arg.find('='));
    if (!is_short && std::find(known.begin(), known.end(), name) == known.end()) {
      return PrintUsageError(who, absl::StrCat("unknown option ", name, DidYouMean(name, known)),
                             who + " --help");
    }
    // CLI11 takes the next argument as the value even when it is an option ("-o --json"
    // would write a file named "--json"): refuse that.
    const CLI::Option* option = sub->get_option_no_throw(name);
    if (option == nullptr) option = app.get_option_no_throw(name);
    if (option != nullptr && name == arg && option->get_items_expected_min() > 0 &&
        j + 1 < args.size()) {
      const std::string next = args[j + 1].substr(0, args[j + 1].find('='));
      if (std::find(known.begin(), known.end(), next) != known.end()) {
        return PrintUsageError(who, absl::StrCat(name, " needs a value (", next, " is an option)"),
                               who + " --help");
      }
    }
  }
  return -1;
}

// CLI11's own messages, in koma's words where they are terse.
std::string ParseErrorText(const CLI::ParseError& e) {
  const std::string what = e.what();
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && absl::StartsWith(what, "input")) {
    return "the input file is required (a path, or - for standard input)";
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    std::string extras = what;
    const size_t colon = extras.find(": ");
    if (colon != std::string::npos) extras = extras.substr(colon + 2);
    return absl::StrCat("unexpected argument(s): ", extras, " (one input file per call)");
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr) {
    // CLI11: "--omit: 1 required N missing".
    const size_t colon = what.find(": ");
    if (colon != std::string::npos && absl::StrContains(what, "missing")) {
      return absl::StrCat(what.substr(0, colon), " needs a value");
    }
    return absl::StrCat("a value is missing: ", what);
  }
  return what;
}

// Flags that say the same thing another way: given on the line, the first replaces the
// preset's second (the omission count and the omission rate).
bool OnLine(const std::vector<std::string>& line, size_t command_index, const std::string& flag) {
  for (size_t j = command_index + 1; j < line.size(); ++j) {
    if (line[j] == "--") break;
    if (line[j] == flag || absl::StartsWith(line[j], flag + "=")) return true;
  }
  return false;
}

// The preset's flags (name value pairs) without those the line states another way.
std::vector<std::string> WithoutReplacedFlags(const std::vector<std::string>& flags,
                                              const std::vector<std::string>& line,
                                              size_t command_index) {
  static const std::vector<std::pair<std::string, std::string>> replaces{
      {"--omit", "--omissions-per-second"},
      {"--omissions", "--omissions-per-second"},
      {"--omissions-per-second", "--omit"},
  };
  std::vector<std::string> kept;
  for (size_t j = 0; j + 1 < flags.size(); j += 2) {
    bool replaced = false;
    for (const auto& [on_line, in_preset] : replaces) {
      replaced = replaced || (flags[j] == in_preset && OnLine(line, command_index, on_line));
    }
    if (!replaced) kept.insert(kept.end(), {flags[j], flags[j + 1]});
  }
  return kept;
}

// The omission count and rate are one setting: the one on the line (the preset's flags are on
// it by now) replaces the other from a --config file. Both on the line stay, for
// CheckSkeletalFlags to refuse.
void KeepOneOmissionSetting(const std::vector<std::string>& line, size_t command_index,
                            SkeletalArgs* args) {
  const bool count = OnLine(line, command_index, "--omit") ||
                     OnLine(line, command_index, "--omissions");
  const bool rate = OnLine(line, command_index, "--omissions-per-second");
  if (rate && !count) args->omissions.reset();
  if (count && !rate) args->omissions_per_second.reset();
}

// --preset NAME: its flags, placed right after the command so that flags given on the line
// win (a repeated option keeps its last value); a --config file's values lose to both.
int ExpandPreset(const std::string& command, size_t command_index, std::vector<std::string>* line) {
  std::string name;
  size_t at = 0;
  size_t width = 0;
  for (size_t j = command_index + 1; j < line->size(); ++j) {
    const std::string& arg = (*line)[j];
    if (arg == "--") break;
    if (arg == "--preset" && j + 1 < line->size()) {
      name = (*line)[j + 1];
      at = j;
      width = 2;
    } else if (absl::StartsWith(arg, "--preset=")) {
      name = arg.substr(9);
      at = j;
      width = 1;
    }
  }
  if (width == 0) return -1;
  const std::vector<std::string>* flags = PresetFlags(command, name);
  const std::string who = "koma " + command;
  if (flags == nullptr) {
    return PrintUsageError(
        who,
        absl::StrCat("--preset: \"", name, "\" is not one of ", absl::StrJoin(PresetNames(), ", ")),
        who + " --help");
  }
  line->erase(line->begin() + static_cast<long>(at), line->begin() + static_cast<long>(at + width));
  const std::vector<std::string> kept = WithoutReplacedFlags(*flags, *line, command_index);
  line->insert(line->begin() + static_cast<long>(command_index) + 1, kept.begin(), kept.end());
  return -1;
}

}  // namespace

const std::vector<std::string>& CommandNames() {
  // batch runs before this parser sees the line (client/main.cc, batch/batch_command.h); it
  // is listed so the messages about commands name it.
  static const std::vector<std::string> names{"skeletal", "curves", "lipblink", "live",
                                              "health",   "batch"};
  return names;
}

int ParseCommandLine(const std::vector<std::string>& args, KomaCommandLine* out) {
  out->parser = std::make_shared<CLI::App>(
      "koma: retime animation into Japanese limited-animation timing", "koma");
  CLI::App& app = *out->parser;
  app.require_subcommand(1);
  app.fallthrough();  // TLS options may stand before or after the subcommand
  app.footer(kGlossary);
  AddGlobalOptions(app, out->tls);
  out->skeletal.server = out->curves.server = out->lip_blink.server = out->health.server =
      DefaultServer();
  AddSkeletalCommand(app, out->skeletal);
  AddCurvesCommand(app, out->curves);
  AddLipBlinkCommand(app, out->lip_blink);
  AddLiveCommand(app, out->live);
  AddHealthCommand(app, out->health);
  // Listed for --help only: main() hands `koma batch ...` to batch::RunIfBatch before this
  // parser sees the line (client/batch/batch_command.h).
  app.add_subcommand("batch",
                     "Retime many clips: files, folders or @lists, across servers, with "
                     "progress, retries and skipping of finished work (koma batch --help)");

  // $KOMA_CONFIG: as --config, unless the line has one.
  std::vector<std::string> line = WithEnvironmentConfig(args);
  std::string command;
  size_t command_index = 0;
  if (int code = PreCheck(app, line, &command, &command_index); code >= 0) return code;
  if (int code = ExpandPreset(command, command_index, &line); code >= 0) return code;
  if (int code = ParseOrExit(app, line,
                             [&command](const CLI::ParseError& e) {
                               const std::string who = command.empty() ? "koma" : "koma " + command;
                               return PrintUsageError(who, ParseErrorText(e), who + " --help");
                             });
      code >= 0) {
    return code;
  }
  for (const CLI::App* sub : app.get_subcommands()) out->command = sub->get_name();  // the one parsed
  if (command == "skeletal") KeepOneOmissionSetting(line, command_index, &out->skeletal);
  return -1;
}

int RunCommandLine(const KomaCommandLine& line) {
  if (absl::Status s = ConfigureTls(line.tls); !s.ok()) {
    PrintStderr(absl::StrCat("koma: ", s.message(), "\n"));
    return kExitUsage;
  }
  if (line.command == "skeletal") return RunSkeletal(line.skeletal);
  if (line.command == "curves") return RunCurves(line.curves);
  if (line.command == "lipblink") return RunLipBlink(line.lip_blink);
  if (line.command == "live") return RunLive(line.live);
  return RunHealth(line.health);
}

int KomaMain(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  KomaCommandLine line;
  if (int code = ParseCommandLine(args, &line); code >= 0) return code;
  return RunCommandLine(line);
}

}  // namespace koma::client

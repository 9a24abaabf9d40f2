#include "client/cli.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <set>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "client/cli_options.h"
#include "client/command_flags.h"
#include "client/command_output.h"
#include "client/flag_values.h"
#include "koma/version.h"

namespace koma::client {
namespace {

constexpr const char* kGlossary =
    "Terms: koma-uchi, drawings held 1 ('on ones'), 2 ('on twos') or 3 frames ('on threes'); "
    "nakanuki (inbetween omission, --omit), removing the fastest inbetween frames; koma-dori "
    "(holds, --hold), repeating a frame where the motion is stillest; genga, the key poses; "
    "tame, a slow start out of a key; tsume, a slow arrival into the next key; the film grid "
    "(--timing-fps), the 24 fps grid drawings are counted on. Exit codes: 0 ok, 1 failure "
    "(RPC error, unreadable or malformed file), 2 usage error. Full reference: docs/usage.md.";

// Options of the top-level app that take a value (and so consume the next argument).
const std::set<std::string>& GlobalValueOptions() {
  static const std::set<std::string> names{"--tls-ca", "--tls-cert", "--tls-key"};
  return names;
}

void AddGlobalOptions(CLI::App& app, TlsFiles& tls) {
  app.add_option("--tls-ca", tls.ca, "PEM CA of the server's certificate: use TLS")
      ->envname("KOMA_TLS_CA");
  app.add_option("--tls-cert", tls.cert, "PEM client certificate (mutual TLS)")
      ->envname("KOMA_TLS_CERT");
  app.add_option("--tls-key", tls.key, "PEM key of --tls-cert")->envname("KOMA_TLS_KEY");
  app.set_version_flag("--version", std::string("koma ") + kVersion,
                       "print the version (koma MAJOR.MINOR.PATCH) and exit");
}

// "--name" for every long name of `cmd`'s options (with the negated forms).
std::vector<std::string> LongNames(const CLI::App* cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* option : cmd->get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_fnames()) {
      if (!absl::StartsWith(name, "--") && name.size() > 1) continue;
      names.push_back(absl::StartsWith(name, "--") ? name : "--" + name);
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

int UsageError(const std::string& who, const std::string& message, const std::string& help) {
  std::fprintf(stderr, "%s: %s\n", who.c_str(), message.c_str());
  std::fprintf(stderr, "Run `%s` for the options.\n", help.c_str());
  return kExitUsage;
}

std::string DidYouMean(const std::string& typed, const std::vector<std::string>& candidates) {
  const std::string close = ClosestMatch(typed, candidates);
  return close.empty() ? "" : absl::StrCat("; did you mean ", close, "?");
}

// koma's checks before CLI11's: a missing or unknown command, an unknown option. Returns -1
// when the line may go to CLI11, else the exit code (after printing). `command` gets the
// command named.
int PreCheck(const CLI::App& app, const std::vector<std::string>& args, std::string* command) {
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
      for (const CLI::App* sub : app.get_subcommands({})) {
        const std::vector<std::string> names = LongNames(sub);
        if (std::find(names.begin(), names.end(), name) != names.end()) {
          return UsageError("koma",
                            absl::StrCat(name, " is an option of `koma ", sub->get_name(),
                                         "`: put it after the command (koma ", sub->get_name(),
                                         " ... ", name, ")"),
                            "koma --help");
        }
      }
      return UsageError("koma",
                        absl::StrCat("unknown option ", name, DidYouMean(name, global)),
                        "koma --help");
    }
    if (absl::StartsWith(arg, "-") && arg.size() > 1) continue;  // CLI11 names it
    break;
  }
  if (i >= args.size()) {
    return UsageError("koma",
                      absl::StrCat("a command is required: ", absl::StrJoin(CommandNames(), ", ")),
                      "koma --help");
  }
  const std::string& typed = args[i];
  if (std::find(CommandNames().begin(), CommandNames().end(), typed) == CommandNames().end()) {
    const std::string close = ClosestMatch(typed, CommandNames());
    return UsageError(
        "koma",
        absl::StrCat("unknown command \"", typed, "\"",
                     close.empty() ? "" : absl::StrCat("; did you mean \"", close, "\"?"),
                     close.empty() ? absl::StrCat(" (commands: ",
                                                  absl::StrJoin(CommandNames(), ", "), ")")
                                   : ""),
        "koma --help");
  }
  *command = typed;
  const CLI::App* sub = app.get_subcommand(typed);
  std::vector<std::string> known = LongNames(sub);
  known.insert(known.end(), global.begin(), global.end());
  const std::string who = "koma " + typed;
  for (size_t j = i + 1; j < args.size(); ++j) {
    const std::string& arg = args[j];
    if (arg == "--") break;
    if (!absl::StartsWith(arg, "--")) continue;
    const std::string name = arg.substr(0, arg.find('='));
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    return UsageError(who, absl::StrCat("unknown option ", name, DidYouMean(name, known)),
                      who + " --help");
  }
  return -1;
}

// CLI11's own messages, in koma's words where they are terse.
std::string ParseErrorText(const CLI::ParseError& e) {
  const std::string what = e.what();
  if (e.get_name() == "RequiredError" && absl::StartsWith(what, "input")) {
    return "the input file is required (a path, or - for standard input)";
  }
  if (e.get_name() == "ExtrasError") {
    std::string extras = what;
    const std::string prefix = "The following arguments were not expected: ";
    if (absl::StartsWith(extras, prefix)) extras = extras.substr(prefix.size());
    return absl::StrCat("unexpected argument(s): ", extras, " (one input file per call)");
  }
  if (e.get_name() == "ArgumentMismatch") return absl::StrCat("a value is missing: ", what);
  return what;
}

}  // namespace

const std::vector<std::string>& CommandNames() {
  static const std::vector<std::string> names{"skeletal", "curves", "lipblink", "health"};
  return names;
}

int ParseCommandLine(const std::vector<std::string>& args, KomaCommandLine* out) {
  CLI::App app{"koma: retime animation into Japanese limited-animation timing", "koma"};
  app.require_subcommand(1);
  app.fallthrough();  // TLS options may stand before or after the subcommand
  app.footer(kGlossary);
  AddGlobalOptions(app, out->tls);
  out->skeletal.server = out->curves.server = out->lip_blink.server = out->health.server =
      DefaultServer();
  AddSkeletalCommand(app, out->skeletal);
  AddCurvesCommand(app, out->curves);
  AddLipBlinkCommand(app, out->lip_blink);
  AddHealthCommand(app, out->health);

  std::string command;
  if (int code = PreCheck(app, args, &command); code >= 0) return code;
  std::vector<std::string> reversed(args.begin() + 1, args.end());
  std::reverse(reversed.begin(), reversed.end());  // CLI11 parses a reversed vector
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string who = command.empty() ? "koma" : "koma " + command;
    return UsageError(who, ParseErrorText(e), who + " --help");
  }
  for (const std::string& name : CommandNames()) {
    if (app.got_subcommand(name)) out->command = name;
  }
  return -1;
}

int RunCommandLine(const KomaCommandLine& line) {
  if (absl::Status s = ConfigureTls(line.tls); !s.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(s.message()).c_str());
    return kExitUsage;
  }
  if (line.command == "skeletal") return RunSkeletal(line.skeletal);
  if (line.command == "curves") return RunCurves(line.curves);
  if (line.command == "lipblink") return RunLipBlink(line.lip_blink);
  return RunHealth(line.health);
}

int KomaMain(int argc, char** argv) {
  const std::vector<std::string> args(argv, argv + argc);
  KomaCommandLine line;
  if (int code = ParseCommandLine(args, &line); code >= 0) return code;
  return RunCommandLine(line);
}

}  // namespace koma::client

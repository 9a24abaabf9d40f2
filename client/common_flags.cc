#include <map>

#include "absl/strings/str_join.h"
#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

const std::vector<std::string>& PresetNames() {
  static const std::vector<std::string> names{"twos", "threes", "snappy", "subtle"};
  return names;
}

const std::vector<std::string>* PresetFlags(const std::string& command, const std::string& name) {
  using Flags = std::vector<std::string>;
  static const std::map<std::string, std::map<std::string, Flags>> presets{
      {"skeletal",
       {{"twos", {"--max-hold", "2"}},
        {"threes", {"--max-hold", "3"}},
        {"snappy", {"--omit", "6", "--max-hold", "3"}},
        {"subtle", {"--omit", "2", "--max-hold", "2"}}}},
      {"curves",
       {{"twos", {"--on", "2"}},
        {"threes", {"--on", "3"}},
        {"snappy", {"--on", "3", "--tame", "1.5", "--tsume", "2"}},
        {"subtle", {"--on", "2"}}}},
      {"lipblink",
       {{"twos", {"--on", "2"}},
        {"threes", {"--on", "3"}},
        {"snappy", {"--on", "2"}},
        {"subtle", {"--on", "3", "--mode", "follow"}}}},
  };
  const auto by_command = presets.find(command);
  if (by_command == presets.end()) return nullptr;
  const auto flags = by_command->second.find(name);
  return flags == by_command->second.end() ? nullptr : &flags->second;
}

void AddPresetFlag(CLI::App* cmd) {
  cmd->add_option_function<std::string>(
         "--preset", [](const std::string&) {},
         "common settings: twos, threes, snappy (more omissions, bunching near keys), subtle; "
         "flags given on the line win (docs/usage.md lists what each sets)")
      ->type_name(absl::StrJoin(PresetNames(), "|"));
}

void AddCommonFlags(CLI::App* cmd, std::string* server, double* deadline_seconds, bool* json,
                    bool* quiet, const std::string& default_deadline) {
  cmd->add_option("--server", *server,
                  "server host:port, or a list a:p,b:p balanced round-robin (default "
                  "$KOMA_SERVER or 127.0.0.1:50051)")
      ->type_name("HOST:PORT")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  AddNumberWithDefault(cmd, "--deadline", deadline_seconds, Above(0),
                       "RPC deadline in seconds (default " + default_deadline + ")")
      ->type_name("SECONDS");
  cmd->add_flag("--json", *json,
                "print the summary as one JSON object on stdout (docs/summary.schema.json); "
                "the human summary goes to stderr");
  cmd->add_flag("-q,--quiet", *quiet, "no human summary (errors still go to stderr)");
}

CLI::App* AddHealthCommand(CLI::App& app, HealthArgs& args) {
  CLI::App* cmd = app.add_subcommand("health", "Ask the server's grpc.health.v1 service");
  cmd->add_option("--service", args.service, "service name (default: the whole server)");
  AddCommonFlags(cmd, &args.server, &args.deadline_seconds, &args.json, &args.quiet, "5");
  return cmd;
}

}  // namespace koma::client

#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

void AddCommonFlags(CLI::App* cmd, std::string* server, double* deadline_seconds, bool* json,
                    bool* quiet, const std::string& default_deadline) {
  cmd->add_option("--server", *server,
                  "server host:port, or a list a:p,b:p balanced round-robin (default "
                  "$KOMA_SERVER or 127.0.0.1:50051)")
      ->type_name("HOST:PORT");
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

// The `koma` command line: subcommands, their flags, and koma's own messages for misuse
// ("koma: unknown command \"skeletl\"; did you mean \"skeletal\"?", "koma skeletal: unknown
// option --omitt; did you mean --omit?"). main() is KomaMain; tests call ParseCommandLine.
#ifndef KOMA_CLIENT_CLI_H_
#define KOMA_CLIENT_CLI_H_

#include <memory>
#include <string>
#include <vector>

#include "client/channel.h"
#include "client/curves_command.h"
#include "client/health_command.h"
#include "client/lip_blink_command.h"
#include "client/live_command.h"
#include "client/skeletal_command.h"

namespace CLI {
class App;
}  // namespace CLI

namespace koma::client {

struct KomaCommandLine {
  std::string command;  // "skeletal", "curves", "lipblink", "live" or "health" after a parse
  TlsFiles tls;
  SkeletalArgs skeletal;
  CurvesArgs curves;
  LipBlinkArgs lip_blink;
  LiveArgs live;
  HealthArgs health;
  // The parser, kept as long as the line: options a command asks after the parse (which were
  // given: LiveArgs::avatar's CLI::Option pointers) must outlive it.
  std::shared_ptr<CLI::App> parser;
};

// The names of the subcommands, in help order.
const std::vector<std::string>& CommandNames();

// Parses `args` (args[0] the program name) into `out`. Returns -1 when the command should
// run; otherwise the exit code to end with, having printed what to print: 0 after --help or
// --version (to stdout), 2 after a usage error (to stderr: "koma[ COMMAND]: message" and
// a line naming the help to read).
int ParseCommandLine(const std::vector<std::string>& args, KomaCommandLine* out);

// Runs a parsed command line: TLS set-up, then the command. Its exit code.
int RunCommandLine(const KomaCommandLine& line);

// main(): ParseCommandLine then RunCommandLine.
int KomaMain(int argc, char** argv);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CLI_H_

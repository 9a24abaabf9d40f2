#include <map>

#include "absl/strings/str_join.h"
#include "client/cli_options.h"
#include "client/command_flags.h"

namespace koma::client {

const std::vector<std::string>& PresetNames() {
  static const std::vector<std::string> names{"twos", "threes", "snappy", "subtle", "paper"};
  return names;
}

const std::vector<std::string>* PresetFlags(const std::string& command, const std::string& name) {
  using Flags = std::vector<std::string>;
  static const std::map<std::string, std::map<std::string, Flags>> presets{
      {"skeletal",
       {{"twos", {"--drawings-per-second", "12"}},
        {"threes", {"--drawings-per-second", "8"}},
        {"snappy", {"--omissions-per-second", "1.5", "--drawings-per-second", "8"}},
        {"subtle", {"--omissions-per-second", "0.5", "--drawings-per-second", "12"}},
        // Naming a count turns the anime defaults off: the paper's 4 omissions, N / 3 holds
        // and on threes (docs/semantics.md, "Defaults: anime timing").
        {"paper", {"--max-hold", "3"}}}},
      {"curves",
       {{"twos", {"--on", "2"}},
        {"threes", {"--on", "3"}},
        {"snappy", {"--on", "3", "--tame", "1.5", "--tsume", "2"}},
        {"subtle", {"--on", "2"}},
        {"paper", {}}}},
      {"lipblink",
       {{"twos", {"--on", "2"}},
        {"threes", {"--on", "3"}},
        {"snappy", {"--on", "2"}},
        {"subtle", {"--on", "3", "--mode", "follow"}},
        {"paper", {}}}},
  };
  const auto by_command = presets.find(command);
  if (by_command == presets.end()) return nullptr;
  const auto flags = by_command->second.find(name);
  return flags == by_command->second.end() ? nullptr : &flags->second;
}

void AddPresetFlag(CLI::App* cmd) {
  cmd->add_option_function<std::string>(
         "--preset", [](const std::string&) {},
         "common settings: twos, threes, snappy (more omissions, bunching near keys), subtle, "
         "paper (skeletal: the paper's counts instead of the anime defaults); "
         "flags given on the line win (docs/usage.md lists what each sets)")
      ->type_name(absl::StrJoin(PresetNames(), "|"));
}

void AddCommonFlags(CLI::App* cmd, CallFlags* flags, const std::string& default_deadline) {
  cmd->add_option("--server", flags->server,
                  "server host:port, or a list a:p,b:p balanced round-robin (default "
                  "$KOMA_SERVER or 127.0.0.1:50051)")
      ->type_name("HOST:PORT")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  AddNumberWithDefault(cmd, "--deadline", &flags->deadline_seconds, Above(0),
                       "RPC deadline in seconds (default " + default_deadline + ")")
      ->type_name("SECONDS");
  cmd->add_flag("--json", flags->json,
                "print the summary as one JSON object on stdout (docs/summary.schema.json); "
                "the human summary goes to stderr");
  cmd->add_flag("-q,--quiet", flags->quiet, "no human summary (errors still go to stderr)");
}

void AddTlsFlags(CLI::App& app, TlsFiles& tls) {
  app.add_option("--tls-ca", tls.ca, "PEM CA of the server's certificate: use TLS")
      ->envname("KOMA_TLS_CA");
  app.add_option("--tls-cert", tls.cert, "PEM client certificate (mutual TLS)")
      ->envname("KOMA_TLS_CERT");
  app.add_option("--tls-key", tls.key, "PEM key of --tls-cert")->envname("KOMA_TLS_KEY");
}

void AddCurveInputFlag(CLI::App* cmd, std::string* input) {
  cmd->add_option("input", *input,
                  "motion3.json, or CSV (frame,<id>,... per frame); - reads standard input")
      ->required()
      ->type_name("IN");
}

void AddReportFlag(CLI::App* cmd, std::string* report) {
  cmd->add_option("--report", *report,
                  "before/after HTML report to write, one self-contained file (docs/report.md)")
      ->type_name("OUT.html");
}

void AddXdtsFlag(CLI::App* cmd, std::string* xdts) {
  cmd->add_option("--xdts", *xdts,
                  "XDTS exposure sheet to write (CLIP STUDIO PAINT, OpenToonz, Tahoma2D, TVPaint; "
                  "docs/formats.md); - writes standard output")
      ->type_name("OUT.xdts");
}

void AddTimingFpsFlag(CLI::App* cmd, std::optional<double>* timing_fps, const std::string& counted,
                      const std::string& frames_of) {
  AddNumber(cmd, "--timing-fps", timing_fps, {},
            "film grid " + counted + " counted on, frames per second (default 24; 0 = count in " +
                frames_of + " own frames; at most 1000)")
      ->type_name("FPS");
}

void AddSendFileFlag(CLI::App* cmd, bool* send_file, const std::string& fields) {
  cmd->add_flag("--send-file", *send_file,
                "send the input file as is (" + fields +
                    ") for the server to parse, instead of the decoded data; the outputs are the "
                    "same bytes");
}

void AddCurveFileFlags(CLI::App* cmd, CurveFileArgs& args, const std::string& timing_counted) {
  AddNumberWithDefault(cmd, "--fps", &args.csv_fps, Above(0),
                       "frames per second of a CSV input (default 30)")
      ->type_name("FPS");
  AddTimingFpsFlag(cmd, &args.timing_fps, timing_counted, "the input's");
  AddChoice(cmd, "--format", &args.format, {"motion3", "csv"},
            "format of the output -o - (default: the input's; an input's format is read from its "
            "contents)");
  AddSendFileFlag(cmd, &args.send_file, "motion3_json or csv_text, csv_fps = --fps");
  cmd->add_option("--timing-from", args.timing_from,
                  "apply the timing of an edited XDTS (the sheet --xdts wrote, edited in CLIP "
                  "STUDIO PAINT, OpenToonz, TVPaint) or, for curves, the drawing sheet CSV "
                  "--timing wrote with --timing-fps 0, instead of computing one; its cells are "
                  "read against koma's answer for the same input and flags (docs/usage.md)")
      ->type_name("SHEET.xdts|TIMING.csv");
  AddPresetFlag(cmd);
  AddCommonFlags(cmd, &args, "60");
}

CLI::App* AddHealthCommand(CLI::App& app, HealthArgs& args) {
  CLI::App* cmd = app.add_subcommand("health", "Ask the server's grpc.health.v1 service");
  cmd->add_option("--service", args.service, "service name (default: the whole server)");
  AddCommonFlags(cmd, &args, "5");
  return cmd;
}

}  // namespace koma::client

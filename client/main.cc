// koma: the reference client. Results on stdout, diagnostics on stderr.
// Exit codes: 0 ok, 1 failure (RPC error, bad file), 2 usage error.
#include <CLI/CLI.hpp>
#include <cstdio>

#include "client/channel.h"
#include "client/curves_command.h"
#include "client/health_command.h"
#include "client/lip_blink_command.h"
#include "client/skeletal_command.h"

namespace {

constexpr int kUsageError = 2;

void AddSkeletal(CLI::App& app, koma::client::SkeletalArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("skeletal", "Retime a BVH mocap clip into anime timing (RetimeSkeletal)");
  cmd->add_option("input", args.input, "BVH file to retime")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args.output, "retimed BVH file to write")->required();
  cmd->add_option("--omit", args.omissions, "inbetween omissions Nio (default 4)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--hold", args.holds, "holds Nhf (default frames / 3)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-hold", args.max_hold, "longest run of one drawing (default 3)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("!--no-keep-length", args.keep_length,
                "do not re-insert duplicates: the clip gets shorter by the omissions");
  cmd->add_flag("--hold-first", args.hold_first, "run holds before omissions");
  cmd->add_flag("--root-relative", args.root_relative,
                "measure speed relative to the root joint (ignore locomotion)");
  cmd->add_option("--timing", args.timing, "timing sheet CSV to write");
  cmd->add_option("--report", args.report, "before/after HTML report to write (docs/report.md)");
  cmd->add_option("--timing-fps", args.timing_fps,
                  "film grid drawings are counted on, frames per second (default 24; 0 = count "
                  "in the BVH's own frames)");
  cmd->add_option_function<std::string>(
         "--output-rate",
         [&args](const std::string& rate) { args.output_at_timing_rate = rate == "timing"; },
         "source (default: the BVH's rate and length) or timing (one frame per grid frame)")
      ->check(CLI::IsMember({"source", "timing"}));
  cmd->add_option("--server", args.server,
                  "server host:port (default $KOMA_SERVER or "
                  "127.0.0.1:50051)");
  cmd->add_option("--deadline", args.deadline_seconds, "RPC deadline in seconds (default 60)")
      ->check(CLI::PositiveNumber);
}

void AddCurves(CLI::App& app, koma::client::CurvesArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "curves", "Draw animation curves on twos/threes with tame/tsume (RetimeCurves)");
  cmd->add_option("input", args.input, "motion3.json, or CSV (frame,<id>,... per frame)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args.output, "motion3.json or .csv to write")->required();
  cmd->add_option("--on", args.frames_per_drawing,
                  "frames per drawing: 2 twos, 3 threes "
                  "(default 3)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--keys", args.keys,
                  "key poses in frames, e.g. 0,10,25 (default: the "
                  "keyframe times)")
      ->delimiter(',');
  cmd->add_option("--tame", args.tame,
                  "tame strength >= 1: bunch drawings near the first key "
                  "(default 1)");
  cmd->add_option("--tsume", args.tsume,
                  "tsume strength >= 1: bunch drawings near the next "
                  "key (default 1)");
  cmd->add_option("--curve-on", args.curve_on, "ID=N: this curve on N (repeatable)");
  cmd->add_option("--fps", args.csv_fps, "frames per second of a CSV input (default 30)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--timing-fps", args.timing_fps,
                  "film grid drawings are counted on, frames per second (default 24; 0 = count "
                  "in the input's own frames)");
  cmd->add_option("--timing", args.timing, "drawing sheet CSV to write");
  cmd->add_option("--report", args.report, "before/after HTML report to write (docs/report.md)");
  cmd->add_option("--server", args.server,
                  "server host:port (default $KOMA_SERVER or "
                  "127.0.0.1:50051)");
  cmd->add_option("--deadline", args.deadline_seconds, "RPC deadline in seconds (default 60)")
      ->check(CLI::PositiveNumber);
}

void AddLipBlink(CLI::App& app, koma::client::LipBlinkArgs& args) {
  CLI::App* cmd =
      app.add_subcommand("lipblink", "Three-drawing mouth flaps and anime blinks (LipBlink)");
  cmd->add_option("input", args.input, "motion3.json, or CSV (frame,<id>,... per frame)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args.output, "motion3.json or .csv to write")->required();
  cmd->add_option("--mouth", args.mouth_ids, "mouth-open curve ids (default ParamMouthOpenY)")
      ->delimiter(',');
  cmd->add_option("--eyes", args.eye_ids,
                  "eye-open curve ids (default ParamEyeLOpen,"
                  "ParamEyeROpen)")
      ->delimiter(',');
  cmd->add_option("--report", args.report, "before/after HTML report to write (docs/report.md)");
  cmd->add_option("--mode", args.mode, "random (the paper) or follow the input (default random)")
      ->check(CLI::IsMember({"random", "follow"}));
  cmd->add_option("--seed", args.seed, "seed of the random mouth shapes and auto-blinks");
  cmd->add_option("--auto-blink", args.auto_blink_mean_s,
                  "insert blinks about every MEAN_S seconds where the eyes do not blink")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--on", args.frames_per_shape, "frames each mouth drawing is held (default 3)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--unlinked-eyes", args.unlinked_eyes, "time each eye's blinks on its own");
  cmd->add_option("--fps", args.csv_fps, "frames per second of a CSV input (default 30)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--timing-fps", args.timing_fps,
                  "film grid mouth and blink holds are counted on, frames per second (default "
                  "24; 0 = count in the input's own frames)");
  cmd->add_option("--server", args.server,
                  "server host:port (default $KOMA_SERVER or "
                  "127.0.0.1:50051)");
  cmd->add_option("--deadline", args.deadline_seconds, "RPC deadline in seconds (default 60)")
      ->check(CLI::PositiveNumber);
}

void AddHealth(CLI::App& app, koma::client::HealthArgs& args) {
  CLI::App* cmd = app.add_subcommand("health", "Ask the server's grpc.health.v1 service");
  cmd->add_option("--server", args.server, "server host:port");
  cmd->add_option("--service", args.service, "service name (default: the whole server)");
  cmd->add_option("--deadline", args.deadline_seconds, "RPC deadline in seconds (default 5)")
      ->check(CLI::PositiveNumber);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"koma: retime animation into Japanese limited-animation timing"};
  app.require_subcommand(1);
  // TLS options may stand before or after the subcommand.
  app.fallthrough();
  koma::client::TlsFiles tls;
  app.add_option("--tls-ca", tls.ca, "PEM CA of the server's certificate: use TLS")
      ->envname("KOMA_TLS_CA");
  app.add_option("--tls-cert", tls.cert, "PEM client certificate (mutual TLS)")
      ->envname("KOMA_TLS_CERT");
  app.add_option("--tls-key", tls.key, "PEM key of --tls-cert")->envname("KOMA_TLS_KEY");
  koma::client::SkeletalArgs skeletal;
  koma::client::CurvesArgs curves;
  koma::client::LipBlinkArgs lip_blink;
  koma::client::HealthArgs health;
  skeletal.server = curves.server = lip_blink.server = health.server =
      koma::client::DefaultServer();
  AddSkeletal(app, skeletal);
  AddCurves(app, curves);
  AddLipBlink(app, lip_blink);
  AddHealth(app, health);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the problem and the usage line to stderr
    return kUsageError;
  }
  if (absl::Status s = koma::client::ConfigureTls(tls); !s.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(s.message()).c_str());
    return kUsageError;
  }
  if (app.got_subcommand("skeletal")) return koma::client::RunSkeletal(skeletal);
  if (app.got_subcommand("curves")) return koma::client::RunCurves(curves);
  if (app.got_subcommand("lipblink")) return koma::client::RunLipBlink(lip_blink);
  return koma::client::RunHealth(health);
}

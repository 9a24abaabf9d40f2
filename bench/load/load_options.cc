#include "bench/load/load_options.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "absl/strings/str_cat.h"

namespace koma::load {
namespace {

constexpr char kDescription[] =
    "koma_load: a ghz-like load generator for koma.v1.Retime.\n"
    "  closed loop: koma_load --rpc skeletal --frames 129 --joints 31 --concurrency 4 "
    "--duration 10\n"
    "  open loop:   koma_load --rpc curves --input a.motion3.json --rate 200 --count 2000\n"
    "Prints count, RPS, latency percentiles (ms) and errors by status code; exit 0 even "
    "with RPC errors unless --fail-on-error, 1 on a failed setup, 2 on a usage error.\n"
    "Calls use the koma client's service config: round_robin over the SERVING servers of a "
    "list, UNAVAILABLE and CANCELLED retried (up to 3 attempts, reported as one call).";

void AddRequestOptions(CLI::App& app, LoadOptions* o) {
  app.add_option("--rpc", o->rpc, "which RPC: skeletal, curves or lipblink")
      ->required()
      ->check(CLI::IsMember({"skeletal", "curves", "lipblink"}));
  app.add_option("--input", o->input,
                 "request from a file: .bvh (skeletal), .motion3.json or .csv (curves, "
                 "lipblink); without it the request is synthesised");
  app.add_option("--frames", o->frames, "synthetic frames")->check(CLI::Range(2, 10'000'000));
  app.add_option("--joints", o->joints, "synthetic joints (skeletal)")
      ->check(CLI::Range(1, 100'000));
  app.add_option("--curves", o->curves, "synthetic curves (curves; lipblink: extra curves)")
      ->check(CLI::Range(0, 1'000'000));
  app.add_option("--form", o->form, "synthetic skeletal form: channels or positions")
      ->check(CLI::IsMember({"channels", "positions"}));
  app.add_option("--seed", o->seed, "seed of the synthetic data (SplitMix64)");
  app.add_option("--max-hold", o->max_hold,
                 "skeletal: the request's max_hold (3: the paper's algorithm, as servers before "
                 "the anime defaults answer a request without counts)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--fps", o->csv_fps, "frames per second of a .csv input")
      ->check(CLI::PositiveNumber);
}

void AddLoadOptions(CLI::App& app, LoadOptions* o) {
  app.add_option("--target,--server", o->target,
                 "host:port, host:port,host:port (round robin) or dns:///name:port")
      ->capture_default_str();
  app.add_option("--concurrency,-c", o->concurrency, "closed loop: outstanding calls")
      ->check(CLI::Range(1, 10'000));
  app.add_option("--channels", o->channels, "gRPC channels (connections) to spread calls over")
      ->check(CLI::Range(1, 1'000));
  app.add_option("--rate", o->rate, "open loop: calls per second on a fixed schedule")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--max-inflight", o->max_inflight,
                 "open loop: most outstanding calls before sends wait (latency still counts "
                 "from the scheduled time)")
      ->check(CLI::Range(1, 100'000));
  app.add_option("--duration", o->duration_s, "measured seconds after the warmup")
      ->check(CLI::PositiveNumber);
  app.add_option("--count,-n", o->count, "measured calls after the warmup")
      ->check(CLI::Range(int64_t{1}, int64_t{100'000'000}));
  app.add_option("--max-duration", o->max_duration_s, "hard cap on warmup + measured time, seconds")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  app.add_option("--warmup", o->warmup_s, "seconds of calls left out of the statistics")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--deadline", o->deadline_s, "per-call deadline, seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--json", o->json_path, "also write the report as JSON to this file");
  app.add_flag("--fail-on-error", o->fail_on_error, "exit 1 when any call failed");
  app.add_flag("--quiet,-q", o->quiet, "no table on stdout");
}

// Cross-option rules CLI11 cannot express; an empty string when all hold.
std::string CheckCombination(const LoadOptions& o) {
  if (o.warmup_s >= o.max_duration_s) return "--warmup must be below --max-duration";
  if (o.duration_s && o.warmup_s + *o.duration_s > o.max_duration_s) {
    return "--warmup + --duration exceeds --max-duration (" + std::to_string(o.max_duration_s) +
           " s); raise --max-duration to run longer";
  }
  if (o.rpc == "skeletal" && !o.input.empty() && o.input.size() >= 4 &&
      o.input.substr(o.input.size() - 4) != ".bvh") {
    return "--input for skeletal must be a .bvh file";
  }
  if (o.rpc != "skeletal" && !o.input.empty() && o.input.size() >= 4 &&
      o.input.substr(o.input.size() - 4) == ".bvh") {
    return "--input for " + o.rpc + " must be a .motion3.json or .csv file";
  }
  return "";
}

}  // namespace

int ParseLoadOptions(int argc, char** argv, LoadOptions* options) {
  CLI::App app(kDescription, "koma_load");
  AddRequestOptions(app, options);
  AddLoadOptions(app, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the problem and a hint to stderr
    return 2;
  }
  if (const std::string problem = CheckCombination(*options); !problem.empty()) {
    std::fprintf(stderr, "koma_load: %s\n%s", problem.c_str(), app.help().c_str());
    return 2;
  }
  if (!options->duration_s && !options->count) options->duration_s = 10.0;
  return -1;
}

}  // namespace koma::load

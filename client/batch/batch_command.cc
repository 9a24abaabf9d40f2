#include "client/batch/batch_command.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/batch/batch_inputs.h"
#include "client/batch/batch_progress.h"
#include "client/batch/batch_rpc.h"
#include "client/batch/batch_runner.h"
#include "client/batch/batch_state.h"
#include "client/channel.h"
#include "client/files.h"

namespace koma::client::batch {
namespace {

constexpr int kFailed = 1;
constexpr int kUsageError = 2;
constexpr int kInterrupted = 130;  // 128 + SIGINT, as shells report it
constexpr double kManifestSaveEveryS = 5.0;  // a killed client loses at most this much

// Everything `koma batch` parses; lives as long as the process (CLI11 holds pointers).
struct BatchCommandArgs {
  std::string rpc;
  std::vector<std::string> inputs;
  std::string out_dir;
  std::string servers;
  int jobs = 0;
  int io_threads = 4;  // file I/O blocks: more threads than cores (measured: docs/benchmarks.md)
  int retries = 7;
  double deadline_seconds = 60.0;
  bool force = false;
  bool quiet = false;
  bool verbose = false;
  bool timing = false;
  std::string summary;
  double progress_every_s = 10.0;
  // Options of the RPCs, mapped onto the single-file commands' argument structs.
  SkeletalArgs skeletal;
  CurvesArgs curves;
  LipBlinkArgs lip_blink;
  std::optional<int> on;             // curves: frames per drawing; lipblink: per mouth shape
  std::optional<double> csv_fps;     // curves, lipblink
  std::optional<double> timing_fps;  // all three
  // Each RPC option with the RPCs it belongs to, to refuse the others' options.
  std::vector<std::pair<CLI::Option*, std::set<std::string>>> owned;
};

void Own(BatchCommandArgs& args, CLI::Option* option, std::set<std::string> rpcs) {
  args.owned.emplace_back(option, std::move(rpcs));
}

void AddRpcOptions(CLI::App* cmd, BatchCommandArgs& a) {
  const std::set<std::string> sk{"skeletal"}, cu{"curves"}, lb{"lipblink"}, curve_files{
                                                                                "curves",
                                                                                "lipblink"};
  // RetimeSkeletal (as `koma skeletal`).
  Own(a, cmd->add_option("--omit", a.skeletal.omissions, "skeletal: inbetween omissions Nio")
             ->check(CLI::NonNegativeNumber), sk);
  Own(a, cmd->add_option("--hold", a.skeletal.holds, "skeletal: holds Nhf")
             ->check(CLI::NonNegativeNumber), sk);
  Own(a, cmd->add_option("--max-hold", a.skeletal.max_hold, "skeletal: longest run of one drawing")
             ->check(CLI::PositiveNumber), sk);
  Own(a, cmd->add_flag("!--no-keep-length", a.skeletal.keep_length,
                       "skeletal: do not re-insert duplicates"), sk);
  Own(a, cmd->add_flag("--hold-first", a.skeletal.hold_first, "skeletal: holds before omissions"),
      sk);
  Own(a, cmd->add_flag("--root-relative", a.skeletal.root_relative,
                       "skeletal: speed relative to the root joint"), sk);
  Own(a, cmd->add_option_function<std::string>(
                 "--output-rate",
                 [&a](const std::string& rate) {
                   a.skeletal.output_at_timing_rate = rate == "timing";
                 },
                 "skeletal: source or timing")
             ->check(CLI::IsMember({"source", "timing"})), sk);
  // RetimeCurves (as `koma curves`).
  Own(a, cmd->add_option("--keys", a.curves.keys, "curves: key poses in frames, e.g. 0,10,25")
             ->delimiter(','), cu);
  Own(a, cmd->add_option("--tame", a.curves.tame, "curves: tame strength >= 1"), cu);
  Own(a, cmd->add_option("--tsume", a.curves.tsume, "curves: tsume strength >= 1"), cu);
  Own(a, cmd->add_option("--curve-on", a.curves.curve_on, "curves: ID=N, this curve on N"), cu);
  // LipBlink (as `koma lipblink`).
  Own(a, cmd->add_option("--mouth", a.lip_blink.mouth_ids, "lipblink: mouth-open curve ids")
             ->delimiter(','), lb);
  Own(a, cmd->add_option("--eyes", a.lip_blink.eye_ids, "lipblink: eye-open curve ids")
             ->delimiter(','), lb);
  Own(a, cmd->add_option("--mode", a.lip_blink.mode, "lipblink: random or follow")
             ->check(CLI::IsMember({"random", "follow"})), lb);
  Own(a, cmd->add_option("--seed", a.lip_blink.seed, "lipblink: seed of mouth shapes and blinks"),
      lb);
  Own(a, cmd->add_option("--auto-blink", a.lip_blink.auto_blink_mean_s,
                         "lipblink: insert blinks about every MEAN_S seconds")
             ->check(CLI::PositiveNumber), lb);
  Own(a, cmd->add_flag("--unlinked-eyes", a.lip_blink.unlinked_eyes,
                       "lipblink: time each eye's blinks on its own"), lb);
  // Shared by two or three RPCs.
  Own(a, cmd->add_option("--on", a.on,
                         "curves: frames per drawing; lipblink: frames per mouth drawing")
             ->check(CLI::PositiveNumber), curve_files);
  Own(a, cmd->add_option("--fps", a.csv_fps, "curves, lipblink: frames per second of CSV inputs")
             ->check(CLI::PositiveNumber), curve_files);
  Own(a, cmd->add_option("--timing-fps", a.timing_fps,
                         "film grid frames per second (default 24; 0 = the input's own frames)"),
      {"skeletal", "curves", "lipblink"});
  Own(a, cmd->add_flag("--timing", a.timing,
                       "skeletal, curves: write each clip's timing sheet beside its output as "
                       "NAME.timing.csv"), {"skeletal", "curves"});
}

// "a:p,b:p" -> one channel per address; a URI (dns:///name:p, ipv4:a:p,b:p) -> one channel
// (gRPC balances within it). Usage error (thrown) for a malformed entry.
std::vector<std::string> SplitServers(const std::string& servers) {
  std::vector<std::string> list;
  if (absl::StrContains(servers, ":///") || absl::StartsWith(servers, "ipv4:") ||
      absl::StartsWith(servers, "ipv6:") || absl::StartsWith(servers, "unix:")) {
    list.push_back(servers);
  } else {
    list = absl::StrSplit(servers, ',', absl::SkipEmpty());
  }
  if (list.empty()) throw CLI::ValidationError("--server", "empty server list");
  for (const std::string& server : list) {
    if (absl::StatusOr<ChannelTarget> target = ResolveTarget(server); !target.ok()) {
      throw CLI::ValidationError("--server", std::string(target.status().message()));
    }
  }
  return list;
}

// The RPC options given for another RPC than the one chosen: a usage error.
void CheckOwnership(const BatchCommandArgs& args) {
  for (const auto& [option, rpcs] : args.owned) {
    if (option->count() > 0 && rpcs.count(args.rpc) == 0) {
      throw CLI::ValidationError(
          option->get_name(),
          absl::StrCat("is an option of ", absl::StrJoin(rpcs, ", "), ", not of ", args.rpc));
    }
  }
}

// TLS from the parent's --tls-ca/--tls-cert/--tls-key (or their KOMA_TLS_* variables).
absl::Status ConfigureTlsFrom(const CLI::App& app) {
  TlsFiles files;
  auto value = [&app](const char* name) {
    const CLI::Option* option = app.get_option_no_throw(name);
    return option != nullptr && option->count() > 0 ? option->as<std::string>() : std::string();
  };
  files.ca = value("--tls-ca");
  files.cert = value("--tls-cert");
  files.key = value("--tls-key");
  return ConfigureTls(files);
}

const char* StatusName(ItemStatus status) {
  switch (status) {
    case ItemStatus::kOk:
      return "ok";
    case ItemStatus::kUpToDate:
      return "up_to_date";
    case ItemStatus::kFailed:
      return "failed";
    default:
      return "not_done";
  }
}

absl::Status WriteSummary(const std::string& path, const BatchCommandArgs& args,
                          const std::vector<std::string>& servers, int jobs,
                          const std::vector<BatchItem>& items, const RunResult& run) {
  nlohmann::json json;
  json["rpc"] = args.rpc;
  json["out_dir"] = args.out_dir;
  json["servers"] = servers;
  json["jobs"] = jobs;
  json["total"] = run.counts.total;
  json["ok"] = run.counts.ok;
  json["up_to_date"] = run.counts.up_to_date;
  json["failed"] = run.counts.failed;
  json["not_done"] = run.counts.total - run.counts.ok - run.counts.up_to_date - run.counts.failed;
  json["retried"] = run.counts.retried;
  json["interrupted"] = run.interrupted;
  json["seconds"] = run.seconds;
  json["clips_per_second"] = run.seconds > 0 ? (run.counts.ok + run.counts.failed) / run.seconds : 0.0;
  nlohmann::json files = nlohmann::json::array();
  for (size_t i = 0; i < items.size(); ++i) {
    const ItemResult& r = run.items[i];
    nlohmann::json file = {{"input", items[i].input},
                           {"output", items[i].output},
                           {"status", StatusName(r.status)},
                           {"attempts", r.attempts}};
    if (!items[i].timing.empty()) file["timing"] = items[i].timing;
    if (!r.server.empty()) file["server"] = r.server;
    if (r.status == ItemStatus::kFailed) {
      file["code"] = r.code;
      file["error"] = r.error;
    }
    files.push_back(std::move(file));
  }
  json["files"] = std::move(files);
  const std::string text = json.dump(1) + "\n";
  if (path == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return absl::OkStatus();
  }
  return WriteFile(path, text);
}

int Run(BatchCommandArgs& args, const CLI::App& root) {
  CheckOwnership(args);
  const std::vector<std::string> servers = SplitServers(args.servers);
  if (absl::Status s = ConfigureTlsFrom(root); !s.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(s.message()).c_str());
    return kUsageError;
  }
  if (args.on) args.curves.frames_per_drawing = args.lip_blink.frames_per_shape = *args.on;
  if (args.csv_fps) args.curves.csv_fps = args.lip_blink.csv_fps = *args.csv_fps;
  if (args.timing_fps) {
    args.skeletal.timing_fps = args.curves.timing_fps = args.lip_blink.timing_fps = *args.timing_fps;
  }
  std::unique_ptr<Rpc> rpc;
  if (args.rpc == "skeletal") {
    rpc = MakeSkeletalRpc(args.skeletal);
  } else if (args.rpc == "curves") {
    // Malformed per-curve or per-segment flags are usage errors, found before any clip is read.
    if (absl::StatusOr<v1::RetimeCurvesRequest> check = BuildCurvesRequest(args.curves, CurveSet{});
        !check.ok()) {
      std::fprintf(stderr, "koma batch: %s\n", std::string(check.status().message()).c_str());
      return kUsageError;
    }
    rpc = MakeCurvesRpc(args.curves);
  } else {
    rpc = MakeLipBlinkRpc(args.lip_blink);
  }

  const std::vector<std::string> extensions = ExtensionsOf(args.rpc);
  absl::StatusOr<std::vector<BatchItem>> items =
      DiscoverInputs(args.inputs, extensions, args.out_dir, args.timing);
  if (!items.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(items.status().message()).c_str());
    return kUsageError;
  }
  if (items->empty()) {
    std::fprintf(stderr, "koma: no input clips (folders are searched for %s)\n",
                 absl::StrJoin(extensions, ", ").c_str());
    return kUsageError;
  }
  std::error_code error;
  std::filesystem::create_directories(args.out_dir, error);
  if (error || !std::filesystem::is_directory(args.out_dir)) {
    std::fprintf(stderr, "koma: -o %s: cannot create the output folder%s%s\n",
                 args.out_dir.c_str(), error ? ": " : "", error ? error.message().c_str() : "");
    return kFailed;
  }

  Manifest manifest = Manifest::Load(args.out_dir);
  const std::string fingerprint = rpc->Fingerprint();
  std::vector<ItemResult> results(items->size());
  if (!args.force) {
    for (size_t i = 0; i < items->size(); ++i) {
      if (manifest.UpToDate((*items)[i], fingerprint)) results[i].status = ItemStatus::kUpToDate;
    }
  }

  RunnerSettings settings;
  settings.servers = servers;
  settings.jobs = args.jobs > 0 ? args.jobs : 2 * static_cast<int>(servers.size());
  settings.io_threads = args.io_threads;
  settings.max_attempts = args.retries + 1;
  settings.deadline_seconds = args.deadline_seconds;
  settings.verbose = args.verbose;
  Progress progress(stderr, isatty(STDERR_FILENO) == 1, args.quiet, args.progress_every_s);
  auto last_save = std::chrono::steady_clock::now();
  const std::function<void(size_t)> on_written = [&](size_t i) {
    manifest.Set((*items)[i], fingerprint);
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_save).count() >= kManifestSaveEveryS) {
      manifest.Save().IgnoreError();  // saved again at the end, where an error is reported
      last_save = now;
    }
  };
  const RunResult run = RunBatch(*items, std::move(results), *rpc, settings, progress, on_written);
  progress.Finish();

  for (size_t i = 0; i < items->size(); ++i) {
    if (run.items[i].status == ItemStatus::kFailed) manifest.Erase((*items)[i].relative);
  }
  int code = run.interrupted ? kInterrupted : run.counts.failed > 0 ? kFailed : 0;
  if (absl::Status s = manifest.Save(); !s.ok()) {
    std::fprintf(stderr, "koma: %s (the next run will redo every clip)\n",
                 std::string(s.message()).c_str());
    if (code == 0) code = kFailed;
  }
  const size_t not_done =
      run.counts.total - run.counts.ok - run.counts.up_to_date - run.counts.failed;
  if (!args.quiet) {
    std::fprintf(stderr,
                 "koma batch: %zu clips: %zu done, %zu up to date, %zu failed, %zu not done; "
                 "%.2f s, %.1f clips/s%s\n",
                 run.counts.total, run.counts.ok, run.counts.up_to_date, run.counts.failed,
                 not_done, run.seconds,
                 run.seconds > 0 ? (run.counts.ok + run.counts.failed) / run.seconds : 0.0,
                 run.interrupted ? " (interrupted)" : "");
  }
  if (!args.summary.empty()) {
    if (absl::Status s = WriteSummary(args.summary, args, servers, settings.jobs, *items, run);
        !s.ok()) {
      std::fprintf(stderr, "koma: --summary: %s\n", std::string(s.message()).c_str());
      if (code == 0) code = kFailed;
    }
  }
  return code;
}

}  // namespace

void AddBatch(CLI::App& app) {
  static BatchCommandArgs args;  // CLI11 keeps pointers to these for the process's life
  args.servers = DefaultServer();
  CLI::App* cmd = app.add_subcommand(
      "batch",
      "Retime many clips: files, folders (searched by extension) or @LIST files, outputs "
      "mirrored under -o OUTDIR, calls spread over every --server, finished work skipped");
  cmd->add_option("rpc", args.rpc, "skeletal, curves or lipblink")
      ->required()
      ->check(CLI::IsMember({"skeletal", "curves", "lipblink"}));
  cmd->add_option("inputs", args.inputs, "files, folders or @LIST (one path per line)")
      ->required();
  cmd->add_option("-o,--output-dir", args.out_dir, "folder the outputs are written under")
      ->required();
  cmd->add_option("--server", args.servers,
                  "servers, comma-separated host:port (one channel each), or one gRPC target "
                  "such as dns:///name:port (default $KOMA_SERVER or 127.0.0.1:50051)");
  cmd->add_option("-j,--jobs", args.jobs, "calls in flight (default 2 per server)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--io-threads", args.io_threads,
                  "threads reading and parsing inputs and writing outputs (default 4)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--retries", args.retries,
                  "times a clip is sent again after UNAVAILABLE or RESOURCE_EXHAUSTED, with "
                  "backoff from 50 ms to 2 s, on another server when there is one (default 7)")
      ->check(CLI::Range(0, 100));
  cmd->add_option("--deadline", args.deadline_seconds, "per call, seconds (default 60)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--force", args.force, "redo every clip, even outputs that are up to date");
  cmd->add_flag("-q,--quiet", args.quiet, "no progress and no summary line (failures still)");
  cmd->add_flag("-v,--verbose", args.verbose, "a line per clip written");
  cmd->add_option("--progress-every", args.progress_every_s,
                  "seconds between progress lines when stderr is not a terminal (default 10)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--summary", args.summary,
                  "write the per-clip status, counts and time as JSON here (- for stdout)");
  AddRpcOptions(cmd, args);
  cmd->callback([cmd] {
    const CLI::App* root = cmd;
    while (root->get_parent() != nullptr) root = root->get_parent();
    const int code = Run(args, *root);
    std::fflush(stdout);
    std::fflush(stderr);
    std::exit(code);
  });
}

}  // namespace koma::client::batch

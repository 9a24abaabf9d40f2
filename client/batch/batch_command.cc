#include "client/batch/batch_command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/batch/batch_inputs.h"
#include "client/batch/batch_progress.h"
#include "client/batch/batch_rpc.h"
#include "client/batch/batch_runner.h"
#include "client/batch/batch_shard.h"
#include "client/batch/batch_state.h"
#include "client/channel.h"
#include "client/cli_options.h"
#include "client/command_flags.h"
#include "client/config_file.h"
#include "client/files.h"

namespace koma::client::batch {
namespace {

constexpr int kFailed = 1;
constexpr int kUsageError = 2;
constexpr int kInterrupted = 130;  // 128 + SIGINT, as shells report it
constexpr double kManifestSaveEveryS = 5.0;  // a killed client loses at most this much

// Options of the single-file commands that name one file or choose how one summary is
// printed: a batch has its own (-o OUTDIR, --timing as a switch, --summary).
constexpr const char* kPerFileOptions[] = {"input",    "-o",           "--timing", "--timing-only",
                                           "--format", "--return-motion", "--report", "--xdts",
                                           "--audio",  "--rhubarb",    "--motion", "--cues",
                                           "--voice-output"};

// The batch's own options on the RPC's subcommand (the RPC's --server, --deadline, --quiet and
// --json stay, bound to its args). Returns them, to leave them out of the fingerprint.
std::set<const CLI::Option*> AddBatchOptions(CLI::App* cmd, BatchCommandArgs& a) {
  for (const char* name : kPerFileOptions) {
    if (CLI::Option* option = cmd->get_option_no_throw(name)) cmd->remove_option(option);
  }
  std::set<const CLI::Option*> own;
  own.insert(cmd->add_option("inputs", a.inputs, "files, folders or @LIST (one path per line)")
                 ->required()
                 ->type_name("IN"));
  own.insert(cmd->add_option("-o,--output-dir", a.out_dir, "folder the outputs are written under")
                 ->required()
                 ->type_name("OUTDIR"));
  if (cmd->get_name() != "lipblink") {  // LipBlink has no sheet
    own.insert(cmd->add_flag("--timing", a.timing,
                             "write each clip's timing sheet beside its output as "
                             "NAME.timing.csv"));
  }
  own.insert(cmd->add_flag("--report", a.report,
                           "write each clip's HTML report beside its output as NAME.report.html"));
  own.insert(cmd->add_flag("--xdts", a.xdts,
                           "write each clip's XDTS exposure sheet beside its output as NAME.xdts"));
  if (cmd->get_name() == "lipblink") {
    // Not one of the batch's own options: it changes the outputs, so it joins the fingerprint.
    cmd->add_flag("--audio-beside", a.audio_beside,
                  "send each input (Spine skeleton, motion3.json, CSV) with the recording of its "
                  "name beside it (hero.json + hero.wav; .wav, .flac, .ogg, .oga, .opus, .mp3), "
                  "as koma lipblink IN --audio REC does; a recording so taken is not an input of "
                  "its own");
  }
  own.insert(cmd->add_option("-j,--jobs", a.jobs, "calls in flight (default 2 per server)")
                 ->check(CLI::Range(1, 4096)));
  own.insert(cmd->add_option("--io-threads", a.io_threads,
                             "threads reading and parsing inputs and writing outputs (default 4)")
                 ->check(CLI::Range(1, 64)));
  own.insert(cmd->add_option("--retries", a.retries,
                             "times a clip is sent again after UNAVAILABLE or RESOURCE_EXHAUSTED, "
                             "after 50 ms doubling to 2 s, to another server when there is one "
                             "(default 7)")
                 ->check(CLI::Range(0, 100)));
  own.insert(cmd->add_flag("--force", a.force, "redo every clip, even up-to-date outputs"));
  own.insert(cmd->add_flag("-v,--verbose", a.verbose, "a line per clip written"));
  own.insert(cmd->add_option("--progress-every", a.progress_every_s,
                             "seconds between progress lines when stderr is not a terminal "
                             "(default 10)")
                 ->check(CLI::PositiveNumber));
  own.insert(cmd->add_option("--summary", a.summary,
                             "write every clip's status, the counts and the time as JSON here "
                             "(- for stdout; with a shard, its tag goes before the extension: "
                             "OUT.3-of-8.json)"));
  CLI::Option* shard =
      cmd->add_option("--shard", a.shard,
                      "do only task K of N (K from 0): N tasks with the same inputs and K = "
                      "0..N-1 together do every clip once, each with its own manifest and "
                      "summary (a render farm's job array)")
          ->type_name("K/N");
  own.insert(shard);
  own.insert(cmd->add_flag("--shard-from-env", a.shard_from_env,
                           "--shard from the scheduler: KOMA_SHARD_INDEX and KOMA_SHARD_COUNT, "
                           "or JOB_COMPLETION_INDEX (Kubernetes Indexed Job) and "
                           "KOMA_SHARD_COUNT, or SLURM_ARRAY_TASK_ID (Slurm job array)")
                 ->excludes(shard));
  // The RPC's common flags, kept (bound to its args) and described as a batch uses them.
  const std::pair<const char*, const char*> common[] = {
      {"--server",
       "servers, comma-separated host:port, one channel each; or one gRPC target such as "
       "dns:///name:port (default $KOMA_SERVER or 127.0.0.1:50051)"},
      {"--deadline", "per call, seconds (default 60)"},
      {"--json", "print the batch summary (as --summary writes it) on stdout"},
      {"--quiet", "no progress and no summary line (failures still go to stderr)"},
      {"--help", nullptr}};
  for (const auto& [name, description] : common) {
    if (CLI::Option* option = cmd->get_option_no_throw(name)) {
      if (description != nullptr) option->description(description);
      own.insert(option);
    }
  }
  return own;
}

// The files --timing-from names: a file itself, a folder's regular files (not below it) in
// name order.
std::vector<std::string> SheetFiles(const std::vector<std::string>& values) {
  std::vector<std::string> files;
  for (const std::string& value : values) {
    std::error_code error;
    if (!std::filesystem::is_directory(value, error)) {
      files.push_back(value);
      continue;
    }
    std::vector<std::string> in_folder;
    for (const auto& entry : std::filesystem::directory_iterator(value, error)) {
      if (entry.is_regular_file(error)) in_folder.push_back(entry.path().string());
    }
    std::sort(in_folder.begin(), in_folder.end());
    files.insert(files.end(), in_folder.begin(), in_folder.end());
  }
  return files;
}

// Every option of `cmd` given on the command line, except `skip`, with its values as typed,
// in the order the command declares them (so argument order and aliases do not matter), as a
// 64-bit FNV-1a digest in hex: the options that shape the outputs. Conservative: a value
// spelled differently (--omit 4 or none) counts as other options, and the clips are redone.
std::string OptionsFingerprint(const std::string& rpc, const CLI::App& cmd,
                               const std::set<const CLI::Option*>& skip) {
  uint64_t hash = 1469598103934665603ULL;
  auto mix = [&hash](const std::string& bytes) {
    const std::string framed = absl::StrCat(bytes.size(), ":", bytes);  // "ab"+"c" != "a"+"bc"
    for (unsigned char c : framed) {
      hash ^= c;
      hash *= 1099511628211ULL;
    }
  };
  mix(rpc);
  for (const CLI::Option* option : cmd.get_options()) {
    if (skip.count(option) > 0 || option->count() == 0) continue;
    mix(option->get_name());
    for (const std::string& value : option->results()) mix(value);
    // --timing-from: the sheets' contents too, so an edited sheet redoes the clips (every
    // clip, for a folder: conservative, as above).
    if (option->get_name() == "--timing-from") {
      for (const std::string& path : SheetFiles(option->results())) {
        mix(path);
        absl::StatusOr<std::string> bytes = ReadFile(path);
        mix(bytes.ok() ? *bytes : std::string(bytes.status().message()));
      }
    }
  }
  return absl::StrFormat("%016x", hash);
}

// "a:p,b:p" -> one channel per address; a URI (dns:///name:p, ipv4:a:p,b:p) -> one channel
// (gRPC balances within it). INVALID_ARGUMENT for a malformed entry.
absl::StatusOr<std::vector<std::string>> SplitServers(const std::string& servers) {
  std::vector<std::string> list;
  if (absl::StrContains(servers, ":///") || absl::StartsWith(servers, "ipv4:") ||
      absl::StartsWith(servers, "ipv6:") || absl::StartsWith(servers, "unix:")) {
    list.push_back(servers);
  } else {
    list = absl::StrSplit(servers, ',', absl::SkipEmpty());
  }
  if (list.empty()) return absl::InvalidArgumentError("--server: empty server list");
  for (const std::string& server : list) {
    if (absl::StatusOr<ChannelTarget> target = ResolveTarget(server); !target.ok()) {
      return absl::InvalidArgumentError(absl::StrCat("--server: ", target.status().message()));
    }
  }
  return list;
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

absl::Status WriteSummary(const std::string& path, const std::string& rpc,
                          const std::string& out_dir, const std::vector<std::string>& servers,
                          int jobs, const Shard& shard, size_t all_clips,
                          const std::vector<BatchItem>& items, const RunResult& run) {
  nlohmann::json json;
  json["rpc"] = rpc;
  json["out_dir"] = out_dir;
  if (!shard.whole()) {
    json["shard"] = {{"index", shard.index}, {"count", shard.count}, {"batch_total", all_clips}};
  }
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
    if (!items[i].audio.empty()) file["audio"] = items[i].audio;
    if (!items[i].timing.empty()) file["timing"] = items[i].timing;
    if (!items[i].report.empty()) file["report"] = items[i].report;
    if (!items[i].xdts.empty()) file["xdts"] = items[i].xdts;
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

int UsageError(const std::string& message) {
  return PrintUsageError("koma batch", message, "koma batch RPC --help");
}

int Run(BatchCommandArgs& args, const std::string& rpc_name, const std::string& fingerprint) {
  // The RPC's --server, --deadline, --quiet and --json (bound to its args by its command).
  const CallFlags& call = rpc_name == "skeletal" ? static_cast<const CallFlags&>(args.skeletal)
                          : rpc_name == "curves" ? static_cast<const CallFlags&>(args.curves)
                                                 : static_cast<const CallFlags&>(args.lip_blink);
  absl::StatusOr<std::vector<std::string>> servers = SplitServers(call.server);
  if (!servers.ok()) return UsageError(std::string(servers.status().message()));
  if (absl::Status s = ConfigureTls(args.tls); !s.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(s.message()).c_str());
    return kUsageError;
  }
  const std::unique_ptr<Rpc> rpc = rpc_name == "skeletal" ? MakeSkeletalRpc(args.skeletal)
                                   : rpc_name == "curves" ? MakeCurvesRpc(args.curves)
                                                          : MakeLipBlinkRpc(args.lip_blink);
  const double deadline_seconds = call.deadline_seconds;
  const bool quiet = call.quiet;
  const bool json = call.json;
  if (json && args.summary == "-") return UsageError("--json and --summary -: one JSON on stdout");
  if (rpc_name == "lipblink" && !args.lip_blink.timing_from.empty() &&
      (args.audio_beside || HasVoice(args.lip_blink) || HasSpineFlags(args.lip_blink))) {
    // As `koma lipblink` refuses them: a sheet times a motion's own mouth and eyes.
    return UsageError("--timing-from: not with a voice (--audio-beside, --audio, --rhubarb) "
                      "or a Spine skeleton");
  }
  if (rpc_name == "lipblink" && args.audio_beside && !args.lip_blink.speech.empty()) {
    // The server would refuse every clip (mouth.speech with a voice): say it once, up front.
    return UsageError("--audio-beside and --speech: each recording gives its clip's speech; "
                      "give one or the other");
  }
  Shard shard;
  if (!args.shard.empty() || args.shard_from_env) {
    absl::StatusOr<Shard> parsed =
        args.shard_from_env
            ? ShardFromEnvironment([](const char* name) { return std::getenv(name); })
            : ParseShard(args.shard);
    if (!parsed.ok()) return UsageError(std::string(parsed.status().message()));
    shard = *parsed;
  }
  std::vector<std::string> summary_paths;  // --summary FILE (the shard's own), stdout for --json
  if (!args.summary.empty()) summary_paths.push_back(ShardedPath(args.summary, shard));
  if (json) summary_paths.push_back("-");

  // lipblink with the Spine flags, curves with --animation: every input must be a skeleton,
  // so folders collect *.json.
  const bool skeletons = rpc_name == "lipblink" ? HasSpineFlags(args.lip_blink)
                         : rpc_name == "curves" ? !args.curves.animations.empty()
                                                : false;
  const std::vector<std::string> extensions = ExtensionsOf(rpc_name, skeletons);
  absl::StatusOr<std::vector<BatchItem>> all_items =
      DiscoverInputs(args.inputs, extensions, args.out_dir, args.timing, args.report,
                     args.xdts, rpc_name == "lipblink" && args.audio_beside);
  if (!all_items.ok()) {
    std::fprintf(stderr, "koma: %s\n", std::string(all_items.status().message()).c_str());
    return kUsageError;
  }
  if (all_items->empty()) {
    std::fprintf(stderr, "koma: no input clips (folders are searched for %s)\n",
                 absl::StrJoin(extensions, ", ").c_str());
    return kUsageError;
  }
  // A shard may be empty (fewer clips than tasks): it succeeds with nothing to do.
  const std::optional<std::vector<BatchItem>> selected =
      shard.whole() ? std::nullopt : std::optional(SelectShard(*all_items, shard));
  const std::vector<BatchItem>* items = selected ? &*selected : &*all_items;
  if (!shard.whole() && !quiet) {
    std::fprintf(stderr, "koma batch: task %s: %zu of the batch's %zu clips\n",
                 absl::StrCat(shard.index, "/", shard.count).c_str(), items->size(),
                 all_items->size());
  }
  std::error_code error;
  std::filesystem::create_directories(args.out_dir, error);
  if (error || !std::filesystem::is_directory(args.out_dir)) {
    std::fprintf(stderr, "koma: -o %s: cannot create the output folder%s%s\n",
                 args.out_dir.c_str(), error ? ": " : "", error ? error.message().c_str() : "");
    return kFailed;
  }

  // Each task its own manifest: tasks on several machines never write the same file.
  Manifest manifest = Manifest::Load(args.out_dir, ShardedPath(Manifest::kFileName, shard));
  std::vector<ItemResult> results(items->size());
  if (!args.force) {
    for (size_t i = 0; i < items->size(); ++i) {
      if (manifest.UpToDate((*items)[i], fingerprint)) results[i].status = ItemStatus::kUpToDate;
    }
  }

  RunnerSettings settings;
  settings.servers = *servers;
  settings.jobs = args.jobs > 0 ? args.jobs : 2 * static_cast<int>(servers->size());
  settings.io_threads = args.io_threads;
  settings.max_attempts = args.retries + 1;
  settings.deadline_seconds = deadline_seconds;
  settings.verbose = args.verbose;
  Progress progress(stderr, isatty(STDERR_FILENO) == 1, quiet, args.progress_every_s);
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
  if (!quiet) {
    std::fprintf(stderr,
                 "koma batch: %zu clips: %zu done, %zu up to date, %zu failed, %zu not done; "
                 "%.2f s, %.1f clips/s%s\n",
                 run.counts.total, run.counts.ok, run.counts.up_to_date, run.counts.failed,
                 not_done, run.seconds,
                 run.seconds > 0 ? (run.counts.ok + run.counts.failed) / run.seconds : 0.0,
                 run.interrupted ? " (interrupted)" : "");
  }
  for (const std::string& summary_path : summary_paths) {
    if (absl::Status s = WriteSummary(summary_path, rpc_name, args.out_dir, *servers, settings.jobs,
                                      shard, all_items->size(), *items, run);
        !s.ok()) {
      std::fprintf(stderr, "koma: --summary: %s\n", std::string(s.message()).c_str());
      if (code == 0) code = kFailed;
    }
  }
  return code;
}

}  // namespace

// The --config file's [skeletal] section is `koma batch skeletal`'s as it is `koma
// skeletal`'s: CLI11 looks a section up among the subcommands of the app that reads the
// file, which here sit under "batch".
class BatchConfig final : public ConfigToml {
 public:
  std::vector<CLI::ConfigItem> from_config(std::istream& in) const override {
    std::vector<CLI::ConfigItem> read = ConfigToml::from_config(in);
    for (CLI::ConfigItem& item : read) {
      if (!item.parents.empty()) item.parents.insert(item.parents.begin(), "batch");
    }
    return read;
  }
};

int ParseBatchCommandLine(const std::vector<std::string>& command_line, BatchCommandLine* out) {
  BatchCommandArgs& args = out->args;
  CLI::App app{"koma batch: retime many clips over every server given", "koma"};
  app.fallthrough();  // the TLS options may stand anywhere
  AddTlsFlags(app, args.tls);
  // Studio defaults, as for the single-file commands (client/config_file.h): $KOMA_CONFIG
  // unless the line names a file; flags on the line win.
  const std::vector<std::string> argv = WithEnvironmentConfig(command_line);
  const std::string config = ConfigFilePath(argv);
  app.set_config("--config", "",
                 "TOML file of defaults: the [skeletal], [curves] and [lipblink] sections of "
                 "koma's --config (also $KOMA_CONFIG); command-line flags win")
      ->type_name("FILE");
  app.config_formatter(std::make_shared<BatchConfig>());
  CLI::App* batch = app.add_subcommand(
      "batch",
      "Retime many clips: files, folders (searched by extension) or @LIST files, outputs "
      "mirrored under -o OUTDIR, calls spread over every --server, finished clips skipped. "
      "After the RPC name come its inputs and the options of that RPC's single-file command.");
  batch->require_subcommand(1);
  args.skeletal.server = args.curves.server = args.lip_blink.server = DefaultServer();
  std::map<std::string, std::pair<CLI::App*, std::set<const CLI::Option*>>> commands;
  const std::vector<CLI::App*> rpcs{AddSkeletalCommand(*batch, args.skeletal),
                                    AddCurvesCommand(*batch, args.curves),
                                    AddLipBlinkCommand(*batch, args.lip_blink)};
  // Checked before the batch options join: the file's keys are the single-file commands'
  // options, so a file koma batch accepts, koma skeletal accepts too.
  if (!config.empty()) {
    if (const int code = CheckConfigFile(app, *batch, config, "koma batch"); code >= 0) return code;
  }
  for (CLI::App* cmd : rpcs) {
    cmd->fallthrough();
    commands[cmd->get_name()] = {cmd, AddBatchOptions(cmd, args)};
  }
  // The RPC named after "batch" (CLI11 would only say that a subcommand is required).
  const auto word = std::find(argv.begin() + 1, argv.end(), "batch");
  if (word != argv.end() && word + 1 == argv.end()) {
    return UsageError("name the RPC: koma batch skeletal|curves|lipblink IN... -o OUTDIR");
  }
  if (word != argv.end() && word + 1 != argv.end() && (*(word + 1))[0] != '-' &&
      commands.count(*(word + 1)) == 0) {
    return UsageError(absl::StrCat("unknown RPC \"", *(word + 1),
                                   "\": skeletal, curves or lipblink"));
  }
  if (int code = ParseOrExit(app, argv,
                             [](const CLI::ParseError& e) {
                               if (dynamic_cast<const CLI::ExtrasError*>(&e) == nullptr) {
                                 return UsageError(e.what());
                               }
                               std::string extras = e.what();
                               if (const size_t colon = extras.find(": ");
                                   colon != std::string::npos) {
                                 extras = extras.substr(colon + 2);
                               }
                               return UsageError(absl::StrCat(
                                   "unknown option or extra argument ", extras,
                                   " (the RPC's options are listed by koma batch RPC --help)"));
                             });
      code >= 0) {
    return code;
  }
  for (const auto& [name, command] : commands) {
    if (command.first->parsed()) {
      out->rpc = name;
      out->fingerprint = OptionsFingerprint(name, *command.first, command.second);
      return -1;
    }
  }
  return UsageError("name the RPC: koma batch skeletal|curves|lipblink IN... -o OUTDIR");
}

int RunIfBatch(int argc, char** argv) {
  // The command word: the first argument that is not a global option (or its value).
  int i = 1;
  while (i < argc && argv[i][0] == '-') {
    const std::string arg = argv[i];
    if (arg == "--tls-ca" || arg == "--tls-cert" || arg == "--tls-key" || arg == "--config") ++i;
    ++i;
  }
  if (i >= argc || std::string(argv[i]) != "batch") return -1;
  BatchCommandLine line;
  if (const int code = ParseBatchCommandLine(std::vector<std::string>(argv, argv + argc), &line);
      code >= 0) {
    return code;
  }
  const int code = Run(line.args, line.rpc, line.fingerprint);
  std::fflush(stdout);
  return code;
}

}  // namespace koma::client::batch

// One file through a `koma` command, in memory: the file's bytes and the command's options in,
// the files `koma COMMAND IN -o OUT --timing T.csv --xdts S.xdts --report R.html [options]`
// writes out, byte for byte, because the CLI's own command runs on them (client/command_io.h
// holds its files, ScopedRetimeChannel takes its call). koma_server's page calls it
// (server/page_jobs.h) on the server's in-process channel; tests compare it with the CLI.
#ifndef KOMA_CLIENT_FILE_JOB_H_
#define KOMA_CLIENT_FILE_JOB_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace koma::client {

struct FileJob {
  std::string command;     // "skeletal", "curves" or "lipblink"
  std::string input_name;  // the file's base name ("pitch.bvh"): its extension names the format
  std::string input;       // the file's bytes
  // Flags after the files, as on koma's command line ({"--preset", "twos"}). The caller
  // chooses which are allowed: a flag naming a file reads or writes nothing outside the job.
  std::vector<std::string> options;
  bool timing = true;  // --timing NAME_timing.csv (skeletal and curves; lipblink has none)
  bool xdts = true;    // --xdts NAME.xdts
  bool report = true;  // --report NAME_report.html
};

struct FileJobFile {
  std::string role;  // "result", "timing", "xdts" or "report"
  std::string name;  // the name the command line gives it ("pitch_anime.bvh")
  std::string bytes;
};

struct FileJobResult {
  // The `koma` line that writes the same files (IN and the outputs in the current folder).
  std::vector<std::string> command_line;
  int exit_code = 0;             // koma's: 0 ok, 1 failure, 2 usage error
  std::string messages;          // what koma printed on standard error
  nlohmann::json summary;        // its --json summary (or error object); null when none
  std::vector<FileJobFile> files;  // in role order; empty unless exit_code is 0
};

// The command line of `job` (without running it). INVALID_ARGUMENT naming the command or the
// input name when the job cannot be a command line (an unknown command, a name with a slash).
absl::StatusOr<std::vector<std::string>> FileJobCommandLine(const FileJob& job);

// Runs `job` as `koma` would, its Retime call on `channel`.
absl::StatusOr<FileJobResult> RunFileJob(const FileJob& job,
                                         const std::shared_ptr<grpc::Channel>& channel);

// What the file is, for a person choosing how to retime it: {"format": key, "format_name",
// "bytes", "commands": [{"command", "flag"}...]} and what its reader tells ("frames", "fps",
// "joints", "curves" (ids), "animations" (names), "seconds", "sample_rate", "channels").
// An unreadable file gets "error" with the reader's message; a format no command reads,
// "commands" empty.
nlohmann::json InspectFile(const std::string& name, const std::string& bytes);

}  // namespace koma::client

#endif  // KOMA_CLIENT_FILE_JOB_H_

// `koma batch skeletal|curves|lipblink IN... -o OUTDIR [options]`: a folder of clips (or a
// list) in one command, across servers, with progress, retries and skipping of finished work.
#ifndef KOMA_CLIENT_BATCH_BATCH_COMMAND_H_
#define KOMA_CLIENT_BATCH_BATCH_COMMAND_H_

#include <string>
#include <vector>

#include "client/channel.h"
#include "client/curves_command.h"
#include "client/lip_blink_command.h"
#include "client/skeletal_command.h"

namespace koma::client::batch {

// Everything `koma batch` parses. The RPC's own flags are the single-file command's (its
// Add*Command), bound to `skeletal`, `curves` or `lip_blink`; the batch's are bound here.
struct BatchCommandArgs {
  TlsFiles tls;
  std::vector<std::string> inputs;
  std::string out_dir;
  int jobs = 0;        // 0: 2 per server
  int io_threads = 4;  // file I/O blocks: more threads than cores (measured: docs/benchmarks.md)
  int retries = 7;
  bool force = false;
  bool verbose = false;
  bool timing = false;  // NAME.timing.csv beside each output
  bool report = false;  // NAME.report.html beside each output
  bool xdts = false;    // NAME.xdts beside each output
  bool audio_beside = false;  // lipblink: each input with the recording of its name beside it
  std::string summary;
  double progress_every_s = 10.0;
  std::string shard;            // --shard K/N; empty: the whole batch
  bool shard_from_env = false;  // --shard-from-env: K and N from the scheduler's variables
  SkeletalArgs skeletal;
  CurvesArgs curves;
  LipBlinkArgs lip_blink;
};

struct BatchCommandLine {
  BatchCommandArgs args;
  std::string rpc;  // "skeletal", "curves" or "lipblink"
  // Digest of the RPC options given (each with its values as typed, in the command's order of
  // declaration, so neither argument order nor aliases matter), the batch's own options left
  // out: equal fingerprints, equal outputs for the same input. Conservative: a value spelled
  // otherwise (--omit 4 against no --omit) counts as other options and the clips are redone.
  std::string fingerprint;
};

// Parses `argv` (argv[0] the program, then "batch", the RPC, ...) into `out`. -1 when the
// batch should run; else the exit code to end with, having printed what to print (0 after
// --help; 2 after a usage error, on stderr).
int ParseBatchCommandLine(const std::vector<std::string>& argv, BatchCommandLine* out);

// When the command line is `koma [--tls-* ...] batch RPC IN... -o OUTDIR [options]`, runs the
// batch and returns its exit code: 0 every clip done (or already up to date), 1 some failed,
// 2 a usage error, 130 when interrupted. Otherwise -1 (another command: main goes on). The
// options of RPC are the single-file command's (client/command_flags.h), less the per-file
// ones (-o, --timing PATH, --timing-only, --format, --return-motion, --report PATH).
int RunIfBatch(int argc, char** argv);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_COMMAND_H_

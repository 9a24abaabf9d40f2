// `koma batch skeletal|curves|lipblink IN... -o OUTDIR [options]`: a folder of clips (or a
// list) in one command, across servers, with progress, retries and skipping of finished work.
#ifndef KOMA_CLIENT_BATCH_BATCH_COMMAND_H_
#define KOMA_CLIENT_BATCH_BATCH_COMMAND_H_

#include <CLI/CLI.hpp>

namespace koma::client::batch {

// Adds the `batch` subcommand to `app` (whose --tls-* options it uses). When the command line
// names it, the batch runs when parsing completes and the process exits with the batch's
// code: 0 every clip done (or already up to date), 1 some failed, 2 a usage error, 130 when
// interrupted. Usage errors found while parsing throw as CLI11's do.
void AddBatch(CLI::App& app);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_COMMAND_H_

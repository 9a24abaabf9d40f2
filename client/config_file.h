// The --config file of studio defaults (docs/usage.md "Presets and config"): a TOML file with
// a [COMMAND] section per command, keys the long option names without "--". `koma COMMAND`
// and `koma batch COMMAND` read the same file with the same checks.
#ifndef KOMA_CLIENT_CONFIG_FILE_H_
#define KOMA_CLIENT_CONFIG_FILE_H_

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace koma::client {

// The file `args` names with --config FILE or --config=FILE (the last one), else
// $KOMA_CONFIG, else "".
std::string ConfigFilePath(const std::vector<std::string>& args);

// "--name" for every long name of `cmd`'s options (with the negated forms), sorted.
std::vector<std::string> LongNames(const CLI::App* cmd);

// "; did you mean X?" when a candidate is close to `typed`, else "".
std::string DidYouMean(const std::string& typed, const std::vector<std::string>& candidates);

// The file at `path`: readable TOML, every section one of koma's commands (CommandNames()),
// every key of a section whose command `commands` has as a subcommand one of that command's
// long options (CLI11 would silently ignore a misspelt key), and every top-level key one of
// `top`'s options. -1 when fine, else the usage exit code after printing the problem as `who`.
int CheckConfigFile(const CLI::App& top, const CLI::App& commands, const std::string& path,
                    const std::string& who);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CONFIG_FILE_H_

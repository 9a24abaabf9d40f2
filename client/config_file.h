// The --config file of studio defaults (docs/usage.md "Presets and config"): a TOML file with
// a [COMMAND] section per command, keys the long option names without "--". `koma COMMAND`
// and `koma batch COMMAND` read the same file with the same checks.
#ifndef KOMA_CLIENT_CONFIG_FILE_H_
#define KOMA_CLIENT_CONFIG_FILE_H_

#include <CLI/CLI.hpp>

#include <istream>
#include <string>
#include <vector>

namespace koma::client {

// CLI11's TOML reader with a UTF-8 byte order mark at the start of the file skipped (Windows
// editors write one; CLI11 would read it as part of the first key). The formatter of every
// app that reads --config; CheckConfigFile has already refused UTF-16 by name.
class ConfigToml : public CLI::ConfigTOML {
 public:
  std::vector<CLI::ConfigItem> from_config(std::istream& in) const override;
};

// `args` with "--config $KOMA_CONFIG" after the program name when that variable is set and
// the line names no --config: CLI11 then reads the file as if it had been typed.
std::vector<std::string> WithEnvironmentConfig(std::vector<std::string> args);

// The file `args` names with --config FILE or --config=FILE (the last one before "--"), else "".
std::string ConfigFilePath(const std::vector<std::string>& args);

// "--name" for every long name of `cmd`'s options (with the negated forms), sorted.
std::vector<std::string> LongNames(const CLI::App* cmd);

// "; did you mean X?" when a candidate is close to `typed`, else "".
std::string DidYouMean(const std::string& typed, const std::vector<std::string>& candidates);

// The file at `path`: readable UTF-8 (a byte order mark skipped; UTF-16 refused by name) TOML, every section one of koma's commands (CommandNames()),
// every key of a section whose command `commands` has as a subcommand one of that command's
// long options (CLI11 would silently ignore a misspelt key), and every top-level key one of
// `top`'s options. -1 when fine, else the usage exit code after printing the problem as `who`.
int CheckConfigFile(const CLI::App& top, const CLI::App& commands, const std::string& path,
                    const std::string& who);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CONFIG_FILE_H_

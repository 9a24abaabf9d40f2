#include "client/config_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "client/cli.h"
#include "client/command_io.h"
#include "client/cli_options.h"
#include "client/flag_values.h"
#include "formats/text_encoding.h"

namespace koma::client {

std::vector<CLI::ConfigItem> ConfigToml::from_config(std::istream& in) const {
  // CLI11 reads the first key from the stream's first byte: step over a byte order mark.
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string_view bom = formats::kUtf8Bom;
  std::istringstream rest(text.compare(0, bom.size(), bom) == 0 ? text.substr(bom.size()) : text);
  return CLI::ConfigTOML::from_config(rest);
}

std::string ConfigFilePath(const std::vector<std::string>& args) {
  std::string path;
  for (size_t j = 1; j < args.size(); ++j) {
    if (args[j] == "--") break;
    if (args[j] == "--config" && j + 1 < args.size()) path = args[j + 1];
    if (absl::StartsWith(args[j], "--config=")) path = args[j].substr(9);
  }
  return path;
}

std::vector<std::string> WithEnvironmentConfig(std::vector<std::string> args) {
  // A command run in memory (the page's jobs) reads no file the scope does not hold.
  const char* from_env = CurrentMemoryCommandIo() ? nullptr : std::getenv("KOMA_CONFIG");
  if (from_env != nullptr && *from_env != '\0' && !args.empty() && ConfigFilePath(args).empty()) {
    args.insert(args.begin() + 1, {"--config", from_env});
  }
  return args;
}

std::vector<std::string> LongNames(const CLI::App* cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* option : cmd->get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_fnames()) {
      if (!absl::StartsWith(name, "--") && name.size() > 1) continue;
      names.push_back(absl::StartsWith(name, "--") ? name : "--" + name);
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

std::string DidYouMean(const std::string& typed, const std::vector<std::string>& candidates) {
  const std::string close = ClosestMatch(typed, candidates);
  return close.empty() ? "" : absl::StrCat("; did you mean ", close, "?");
}

int CheckConfigFile(const CLI::App& top, const CLI::App& commands, const std::string& path,
                    const std::string& who) {
  const std::string help = who + " --help";
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    return PrintUsageError(
        who, absl::StrCat("--config ", path, ": cannot read: ", std::strerror(errno)), help);
  }
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (const absl::Status encoding = formats::SkipUtf8Bom(text).status(); !encoding.ok()) {
    return PrintUsageError(who, absl::StrCat("--config ", path, ": ", encoding.message()), help);
  }
  std::istringstream in(text);
  std::vector<CLI::ConfigItem> items;
  try {
    items = ConfigToml().from_config(in);
  } catch (const CLI::ParseError& e) {
    return PrintUsageError(who, absl::StrCat("--config ", path, ": ", e.what()), help);
  }
  for (const CLI::ConfigItem& item : items) {
    if (item.name == "++" || item.name == "--") continue;
    const CLI::App* owner = &top;
    std::string section = "top level";
    if (!item.parents.empty()) {
      section = "[" + item.parents[0] + "]";
      if (std::find(CommandNames().begin(), CommandNames().end(), item.parents[0]) ==
          CommandNames().end()) {
        return PrintUsageError(who,
                               absl::StrCat("--config ", path, ": unknown section ", section,
                                            DidYouMean(item.parents[0], CommandNames())),
                               help);
      }
      const std::vector<const CLI::App*> subs = commands.get_subcommands(
          [&item](const CLI::App* sub) { return sub->get_name() == item.parents[0]; });
      if (subs.empty()) continue;  // a command this line does not run (batch: [health])
      owner = subs.front();
    }
    std::vector<std::string> keys;
    for (const std::string& name : LongNames(owner)) keys.push_back(name.substr(2));
    if (item.parents.size() > 1 || std::find(keys.begin(), keys.end(), item.name) == keys.end()) {
      return PrintUsageError(who,
                             absl::StrCat("--config ", path, ": ", section, " ", item.name,
                                          ": unknown option", DidYouMean(item.name, keys)),
                             help);
    }
  }
  return -1;
}

}  // namespace koma::client

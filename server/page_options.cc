#include "server/page_options.h"

#include <civetweb.h>

#include <algorithm>
#include <regex>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"

namespace koma::server {
namespace {

constexpr unsigned kMaxQueryPairs = 32;

bool OfForm(const std::string& value, absl::string_view form) {
  if (form == "int") return std::regex_match(value, std::regex("[0-9]{1,9}"));
  if (form == "seed") return std::regex_match(value, std::regex("[0-9]{1,20}"));
  if (form == "number") {
    return std::regex_match(value, std::regex("[0-9]{1,9}(\\.[0-9]{1,9})?"));
  }
  for (absl::string_view word : absl::StrSplit(form, '|')) {
    if (value == word) return true;
  }
  return false;
}

std::string FormText(absl::string_view form) {
  if (form == "int" || form == "seed") return "a whole number";
  if (form == "number") return "a number";
  return absl::StrCat("one of ", absl::StrJoin(absl::StrSplit(form, '|'), ", "));
}

}  // namespace

absl::StatusOr<std::vector<std::pair<std::string, std::string>>> SplitQuery(
    std::string_view query) {
  std::string data(query);  // split in place by civetweb
  mg_header fields[kMaxQueryPairs + 1];
  const int count = mg_split_form_urlencoded(data.data(), fields, kMaxQueryPairs + 1);
  if (count < 0) return absl::InvalidArgumentError("the query cannot be read");
  if (count > static_cast<int>(kMaxQueryPairs)) {
    return absl::InvalidArgumentError(
        absl::StrCat("the query has more than ", kMaxQueryPairs, " parameters"));
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  for (int i = 0; i < count; ++i) {
    std::string name(fields[i].name);
    for (const auto& pair : pairs) {
      if (pair.first == name) {
        return absl::InvalidArgumentError(absl::StrCat("query parameter ", name, " given twice"));
      }
    }
    pairs.emplace_back(std::move(name), fields[i].value ? fields[i].value : "");
  }
  return pairs;
}

const std::vector<PageOption>& PageOptions() {
  static const std::vector<PageOption> options{
      {"preset", "--preset", {"skeletal", "curves", "lipblink"}, "twos|threes|snappy|subtle"},
      {"omit", "--omit", {"skeletal"}, "int"},
      {"omissions_per_second", "--omissions-per-second", {"skeletal"}, "number"},
      {"drawings_per_second", "--drawings-per-second", {"skeletal"}, "number"},
      {"on", "--on", {"curves", "lipblink"}, "int"},
      {"tame", "--tame", {"curves"}, "number"},
      {"tsume", "--tsume", {"curves"}, "number"},
      {"mode", "--mode", {"lipblink"}, "random|follow"},
      {"auto_blink", "--auto-blink", {"lipblink"}, "number"},
      {"seed", "--seed", {"lipblink"}, "seed"},
      {"timing_fps", "--timing-fps", {"skeletal", "curves", "lipblink"}, "number"},
  };
  return options;
}

absl::StatusOr<client::FileJob> PageJobFromQuery(std::string_view query, std::string body) {
  absl::StatusOr<std::vector<std::pair<std::string, std::string>>> pairs = SplitQuery(query);
  if (!pairs.ok()) return pairs.status();
  client::FileJob job;
  job.input = std::move(body);
  for (const auto& [name, value] : *pairs) {
    if (name == "command") job.command = value;
    if (name == "name") job.input_name = value;
  }
  if (job.command.empty() || job.input_name.empty()) {
    return absl::InvalidArgumentError(
        "the query needs command=skeletal|curves|lipblink and name=FILE");
  }
  for (const auto& [name, value] : *pairs) {
    if (name == "command" || name == "name") continue;
    if (name == "timing" || name == "xdts" || name == "report") {
      if (value != "0" && value != "1") {
        return absl::InvalidArgumentError(absl::StrCat(name, "=", value, ": give 0 or 1"));
      }
      (name == "timing" ? job.timing : name == "xdts" ? job.xdts : job.report) = value == "1";
      continue;
    }
    const auto& options = PageOptions();
    const auto option =
        std::find_if(options.begin(), options.end(),
                     [&name = name](const PageOption& o) { return name == o.name; });
    if (option == options.end()) {
      return absl::InvalidArgumentError(absl::StrCat("unknown parameter \"", name, "\""));
    }
    if (std::find(option->commands.begin(), option->commands.end(), job.command) ==
        option->commands.end()) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, ": koma ", job.command, " has no ", option->flag, " (it is for koma ",
                       absl::StrJoin(option->commands, ", koma "), ")"));
    }
    if (value.empty()) continue;  // the page sends an untouched field empty: the default
    if (!OfForm(value, option->form)) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, "=", value, ": must be ", FormText(option->form)));
    }
    job.options.push_back(option->flag);
    job.options.push_back(value);
  }
  return job;
}

}  // namespace koma::server

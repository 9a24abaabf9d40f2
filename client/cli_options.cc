#include "client/cli_options.h"

#include <algorithm>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "client/command_io.h"
#include "client/command_output.h"

namespace koma::client {
namespace {

template <typename T>
T OrThrow(absl::StatusOr<T> value) {
  if (!value.ok()) ThrowFlagError(value.status());
  return *std::move(value);
}

// Every value of every occurrence, split at commas.
std::vector<std::string> Items(const std::vector<std::string>& values) {
  std::vector<std::string> items;
  for (const std::string& value : values) {
    for (absl::string_view part : absl::StrSplit(value, ',')) {
      items.emplace_back(absl::StripAsciiWhitespace(part));
    }
  }
  return items;
}

// An option of one value (the last of repeats wins): `parse(flag, text)` gives what *out
// takes, or throws FlagValueError with koma's message; `flag` is the first long name.
template <typename Out, typename Parse>
CLI::Option* AddParsed(CLI::App* cmd, const std::string& names, Out* out,
                       const std::string& type_name, const std::string& help, Parse parse) {
  const std::string flag = FirstLongName(names);
  return cmd
      ->add_option_function<std::string>(
          names, [=](const std::string& text) { *out = parse(flag, text); }, help)
      ->type_name(type_name)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

// A list option, repeatable and comma-separated (values add up): `parse(flag, item)` gives
// each element, or throws.
template <typename Element, typename Parse>
CLI::Option* AddParsedList(CLI::App* cmd, const std::string& names, std::vector<Element>* out,
                           const std::string& type_name, const std::string& help, Parse parse) {
  const std::string flag = FirstLongName(names);
  return cmd
      ->add_option_function<std::vector<std::string>>(
          names,
          [=](const std::vector<std::string>& values) {
            out->clear();
            for (const std::string& item : Items(values)) out->push_back(parse(flag, item));
          },
          help)
      ->type_name(type_name)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

}  // namespace

int PrintUsageError(const std::string& who, const std::string& message, const std::string& help) {
  PrintStderr(absl::StrCat(who, ": ", message, "\nRun `", help, "` for the options.\n"));
  return kExitUsage;
}

int ParseOrExit(CLI::App& app, const std::vector<std::string>& args,
                const std::function<int(const CLI::ParseError&)>& on_error) {
  std::vector<std::string> reversed(args.begin() + 1, args.end());
  std::reverse(reversed.begin(), reversed.end());  // CLI11 parses a reversed vector
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return on_error(e);
  }
  return -1;
}

void ThrowFlagError(const absl::Status& status) {
  throw FlagValueError(std::string(status.message()));
}

std::string FirstLongName(const std::string& names) {
  for (absl::string_view name : absl::StrSplit(names, ',')) {
    absl::ConsumePrefix(&name, "!");
    if (absl::StartsWith(name, "--")) return std::string(name);
  }
  return names;
}

CLI::Option* AddWholeNumber(CLI::App* cmd, const std::string& names, std::optional<int>* out,
                            int64_t min, int64_t max, const std::string& help) {
  return AddParsed(cmd, names, out, "N", help,
                   [=](const std::string& flag, const std::string& text) {
                     return static_cast<int>(OrThrow(ParseWholeNumber(flag, text, min, max)));
                   });
}

CLI::Option* AddSeed(CLI::App* cmd, const std::string& names, std::optional<uint64_t>* out,
                     const std::string& help) {
  return AddParsed(cmd, names, out, "N", help,
                   [](const std::string& flag, const std::string& text) {
                     return OrThrow(ParseUnsigned64(flag, text));
                   });
}

CLI::Option* AddNumber(CLI::App* cmd, const std::string& names, std::optional<double>* out,
                       const NumberBounds& bounds, const std::string& help) {
  return AddParsed(cmd, names, out, "X", help,
                   [=](const std::string& flag, const std::string& text) {
                     return OrThrow(ParseNumber(flag, text, bounds));
                   });
}

CLI::Option* AddNumberWithDefault(CLI::App* cmd, const std::string& names, double* out,
                                  const NumberBounds& bounds, const std::string& help) {
  return AddParsed(cmd, names, out, "X", help,
                   [=](const std::string& flag, const std::string& text) {
                     return OrThrow(ParseNumber(flag, text, bounds));
                   });
}

CLI::Option* AddBool(CLI::App* cmd, const std::string& names, std::optional<bool>* out,
                     const std::string& help) {
  return AddParsed(cmd, names, out, "true|false", help,
                   [](const std::string& flag, const std::string& text) {
                     return OrThrow(ParseBool(flag, text));
                   });
}

CLI::Option* AddChoice(CLI::App* cmd, const std::string& names, std::string* out,
                       const std::vector<std::string>& choices, const std::string& help) {
  return AddParsed(cmd, names, out, absl::StrJoin(choices, "|"), help,
                   [=](const std::string& flag, const std::string& text) {
                     if (std::find(choices.begin(), choices.end(), text) == choices.end()) {
                       throw FlagValueError(absl::StrCat(flag, ": \"", text, "\" is not one of ",
                                                         absl::StrJoin(choices, ", ")));
                     }
                     return text;
                   });
}

CLI::Option* AddWholeNumberList(CLI::App* cmd, const std::string& names, std::vector<int>* out,
                                int64_t min, int64_t max, const std::string& help) {
  return AddParsedList(cmd, names, out, "N,...", help,
                       [=](const std::string& flag, const std::string& item) {
                         return static_cast<int>(OrThrow(ParseWholeNumber(flag, item, min, max)));
                       });
}

CLI::Option* AddNumberList(CLI::App* cmd, const std::string& names, std::vector<double>* out,
                           const NumberBounds& bounds, int count, const std::string& help) {
  return AddParsed(cmd, names, out, "X,...", help,
                   [=](const std::string& flag, const std::string& text) {
                     return OrThrow(ParseNumberList(flag, text, bounds, count));
                   });
}

CLI::Option* AddStringList(CLI::App* cmd, const std::string& names, std::vector<std::string>* out,
                           const std::string& help) {
  return AddParsedList(cmd, names, out, "ID,...", help,
                       [](const std::string& flag, const std::string& item) {
                         if (item.empty()) {
                           throw FlagValueError(absl::StrCat(flag, ": empty name in the list"));
                         }
                         return item;
                       });
}

CLI::Option* AddIntervals(CLI::App* cmd, const std::string& names, std::vector<FlagInterval>* out,
                          const std::string& help) {
  return AddParsedList(cmd, names, out, "BEGIN-END,...", help,
                       [](const std::string& flag, const std::string& item) {
                         return OrThrow(ParseInterval(flag, item));
                       });
}

}  // namespace koma::client

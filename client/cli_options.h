// CLI11 options whose values are parsed by flag_values.h, so every bad value gets koma's
// message ("--omit: \"abc\" is not a whole number") instead of CLI11's, and is a usage error.
// A repeated scalar option keeps its last value; list options add up over repeats.
#ifndef KOMA_CLIENT_CLI_OPTIONS_H_
#define KOMA_CLIENT_CLI_OPTIONS_H_

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "client/flag_values.h"

namespace koma::client {

// A bad flag value: CLI11 reports it as a usage error (exit 2); what() is the whole message.
class FlagValueError : public CLI::ParseError {
 public:
  explicit FlagValueError(const std::string& message)
      : CLI::ParseError("FlagValueError", message, CLI::ExitCodes::ValidationError) {}
};

// "WHO: message", then "Run `HELP` for the options." on stderr; returns 2 (kExitUsage, a
// usage error). Every usage error of `koma` and `koma batch` is printed by this.
int PrintUsageError(const std::string& who, const std::string& message, const std::string& help);

// CLI11 parses args[1..] (args[0] the program) into `app`: -1 when the line parsed. After
// --help or --version CLI11 prints them and this returns its exit code (0); after any other
// CLI11 error, what `on_error` returns (having printed koma's message).
int ParseOrExit(CLI::App& app, const std::vector<std::string>& args,
                const std::function<int(const CLI::ParseError&)>& on_error);

// Throws FlagValueError with the status's message.
[[noreturn]] void ThrowFlagError(const absl::Status& status);

// The first "--name" of a CLI11 names list ("--omit,--omissions" -> "--omit").
std::string FirstLongName(const std::string& names);

CLI::Option* AddWholeNumber(CLI::App* cmd, const std::string& names, std::optional<int>* out,
                            int64_t min, int64_t max, const std::string& help);
CLI::Option* AddSeed(CLI::App* cmd, const std::string& names, std::optional<uint64_t>* out,
                     const std::string& help);
CLI::Option* AddNumber(CLI::App* cmd, const std::string& names, std::optional<double>* out,
                       const NumberBounds& bounds, const std::string& help);
// A number with a default (--deadline, --fps): `out` keeps it when the flag is absent.
CLI::Option* AddNumberWithDefault(CLI::App* cmd, const std::string& names, double* out,
                                  const NumberBounds& bounds, const std::string& help);
CLI::Option* AddBool(CLI::App* cmd, const std::string& names, std::optional<bool>* out,
                     const std::string& help);
// One of `choices`; anything else: "--mode: \"x\" is not one of random, follow".
CLI::Option* AddChoice(CLI::App* cmd, const std::string& names, std::string* out,
                       const std::vector<std::string>& choices, const std::string& help);
// Comma-separated whole numbers, repeatable (values add up).
CLI::Option* AddWholeNumberList(CLI::App* cmd, const std::string& names, std::vector<int>* out,
                                int64_t min, int64_t max, const std::string& help);
// Comma-separated numbers; `count` > 0: exactly that many.
CLI::Option* AddNumberList(CLI::App* cmd, const std::string& names, std::vector<double>* out,
                           const NumberBounds& bounds, int count, const std::string& help);
// Comma-separated strings, repeatable (values add up); each must be non-empty.
CLI::Option* AddStringList(CLI::App* cmd, const std::string& names, std::vector<std::string>* out,
                           const std::string& help);
// Comma-separated frame intervals BEGIN-END, repeatable.
CLI::Option* AddIntervals(CLI::App* cmd, const std::string& names, std::vector<FlagInterval>* out,
                          const std::string& help);

}  // namespace koma::client

#endif  // KOMA_CLIENT_CLI_OPTIONS_H_

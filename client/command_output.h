// How every `koma` command reports: the human summary (stdout, or stderr when stdout carries
// a file or --json; dropped with --quiet), the --json summary (one object on stdout, schema in
// docs/summary.schema.json) and errors ("koma: ..." on stderr, and with --json an error object
// on stdout) with hints a person can act on.
#ifndef KOMA_CLIENT_COMMAND_OUTPUT_H_
#define KOMA_CLIENT_COMMAND_OUTPUT_H_

#include <grpcpp/grpcpp.h>

#include <nlohmann/json.hpp>
#include <string>

#include "absl/status/status.h"

namespace koma::client {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // RPC error, unreadable or malformed file, write error
inline constexpr int kExitUsage = 2;    // flags that cannot work

// The lines koma prints for a failed RPC to `server`, without the "koma: " prefix:
// "CODE: message", and for UNAVAILABLE (server down or unreachable) and DEADLINE_EXCEEDED a
// second line "hint: ..." naming the server and what to do.
std::string RpcErrorText(const grpc::Status& status, const std::string& server);

class CommandOutput {
 public:
  // `command`: "skeletal", "curves", "lipblink", "health".
  CommandOutput(std::string command, bool json, bool quiet, std::string server = "");

  // "koma: message" on stderr (with --json also the error object on stdout); returns 1.
  int Failure(const absl::Status& status) const;
  // As Failure; returns 2 (a usage error found after parsing, e.g. flags that conflict).
  int UsageFailure(const absl::Status& status) const;
  // RpcErrorText on stderr, each line after "koma: "; with --json the error object; returns 1.
  int RpcFailure(const grpc::Status& status) const;

  // A successful run: `text` (the human summary, lines ending in "\n") to stdout, or to
  // stderr when `stdout_taken` (an output went to "-") or --json; nothing with --quiet. With
  // --json, `summary` with "koma_version", "command" and "status": "ok" added on stdout.
  void Success(const std::string& text, nlohmann::json summary, bool stdout_taken) const;

  // {"koma_version", "command", "status"}: the fields every summary starts with.
  nlohmann::json Header(const std::string& status) const;

 private:
  void PrintJsonError(const std::string& code, const std::string& message, int exit_code) const;

  std::string command_;
  bool json_;
  bool quiet_;
  std::string server_;
};

// "  report: PATH\n" for the human summary when --report was given, else "".
std::string ReportLine(const std::string& report_path);
// "  exposure sheet (XDTS): PATH\n" when --xdts was given, else "".
std::string XdtsLine(const std::string& xdts_path);
// "  given: the timing of SHEET\n" when --timing-from was given (curves, lipblink), else "".
std::string TimingFromLine(const std::string& sheet_path);

}  // namespace koma::client

#endif  // KOMA_CLIENT_COMMAND_OUTPUT_H_

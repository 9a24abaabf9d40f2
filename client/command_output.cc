#include "client/command_output.h"

#include <cstdio>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "client/command_io.h"
#include "client/files.h"
#include "koma/version.h"

namespace koma::client {
namespace {

std::string CodeName(absl::StatusCode code) { return absl::StatusCodeToString(code); }

void PrintLines(const std::string& text) {
  for (absl::string_view line : absl::StrSplit(text, '\n', absl::SkipEmpty())) {
    PrintStderr(absl::StrCat("koma: ", line, "\n"));
  }
}

}  // namespace

std::string RpcErrorText(const grpc::Status& status, const std::string& server) {
  const auto code = static_cast<absl::StatusCode>(status.error_code());
  std::string text = absl::StrCat(CodeName(code), ": ");
  switch (status.error_code()) {
    case grpc::StatusCode::UNAVAILABLE:
      absl::StrAppend(&text, "cannot reach koma_server at ", server,
                      " (gRPC: ", status.error_message(), ")\n", "hint: is koma_server running at ",
                      server, "? Start it with `koma_server --address=", server,
                      "`, or point --server (or $KOMA_SERVER) at a running one");
      break;
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      absl::StrAppend(&text, "no answer from ", server,
                      " within the deadline (gRPC: ", status.error_message(), ")\n",
                      "hint: a long clip may need more time: raise --deadline (seconds)");
      break;
    default:
      absl::StrAppend(&text, status.error_message());
  }
  return text;
}

CommandOutput::CommandOutput(std::string command, bool json, bool quiet, std::string server)
    : command_(std::move(command)), json_(json), quiet_(quiet), server_(std::move(server)) {}

nlohmann::json CommandOutput::Header(const std::string& status) const {
  nlohmann::json header = nlohmann::json::object();
  header["koma_version"] = kVersion;
  header["command"] = command_;
  header["status"] = status;
  return header;
}

void CommandOutput::PrintJsonError(const std::string& code, const std::string& message,
                                   int exit_code) const {
  if (!json_) return;
  nlohmann::json error = Header("error");
  error["exit_code"] = exit_code;
  error["error"] = {{"code", code}, {"message", message}};
  PrintStdout(error.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

int CommandOutput::Failure(const absl::Status& status) const {
  const std::string message(status.message());
  PrintLines(message);
  PrintJsonError(CodeName(status.code()), message, kExitFailure);
  return kExitFailure;
}

int CommandOutput::UsageFailure(const absl::Status& status) const {
  const std::string message(status.message());
  PrintStderr(absl::StrCat("koma ", command_, ": ", message, "\n"));
  PrintJsonError("USAGE", message, kExitUsage);
  return kExitUsage;
}

int CommandOutput::RpcFailure(const grpc::Status& status) const {
  const std::string text = RpcErrorText(status, server_);
  PrintLines(text);
  PrintJsonError(CodeName(static_cast<absl::StatusCode>(status.error_code())),
                 status.error_message(), kExitFailure);
  return kExitFailure;
}

void CommandOutput::Success(const std::string& text, nlohmann::json summary,
                            bool stdout_taken) const {
  if (!quiet_) {
    if (stdout_taken || json_) {
      PrintStderr(text);
    } else {
      PrintStdout(text);
    }
  }
  if (!json_) return;
  nlohmann::json out = Header("ok");
  for (auto& [key, value] : summary.items()) out[key] = std::move(value);
  PrintStdout(out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

std::string XdtsLine(const std::string& xdts_path) {
  return xdts_path.empty() ? std::string() : "  exposure sheet (XDTS): " + xdts_path + "\n";
}

std::string TimingFromLine(const std::string& sheet_path) {
  return sheet_path.empty() ? std::string()
                            : "  given: the timing of " + InputName(sheet_path) + "\n";
}

std::string ReportLine(const std::string& report_path) {
  return report_path.empty() ? std::string() : "  report: " + report_path + "\n";
}

}  // namespace koma::client

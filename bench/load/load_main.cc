// koma_load: a ghz-like load generator for koma.v1.Retime. Flags are listed by --help.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "bench/load/load_options.h"
#include "bench/load/load_report.h"
#include "bench/load/load_request.h"
#include "bench/load/load_runner.h"

namespace {

constexpr double kConnectTimeoutS = 5.0;  // seconds each channel may take to connect

int Fail(const std::string& message) {
  std::fprintf(stderr, "koma_load: %s\n", message.c_str());
  return 1;
}

bool AllConnected(const std::vector<std::shared_ptr<grpc::Channel>>& channels) {
  const auto deadline = std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int>(kConnectTimeoutS * 1000));
  for (const auto& channel : channels) {
    if (!channel->WaitForConnected(deadline)) return false;
  }
  return true;
}

std::string Mode(const koma::load::LoadOptions& o) {
  const std::string channels = absl::StrCat(o.channels, o.channels == 1 ? " channel" : " channels");
  if (o.rate > 0.0) {
    return absl::StrCat("open loop, ", o.rate, " calls/s (max ", o.max_inflight, " in flight), ",
                        channels);
  }
  return absl::StrCat("closed loop, concurrency ", o.concurrency, ", ", channels);
}

}  // namespace

int main(int argc, char** argv) {
  koma::load::LoadOptions options;
  if (const int code = koma::load::ParseLoadOptions(argc, argv, &options); code >= 0) {
    return code;
  }
  auto target = koma::load::ResolveTarget(options.target);
  if (!target.ok()) {
    std::fprintf(stderr, "koma_load: %s\n", std::string(target.status().message()).c_str());
    return 2;
  }
  auto request = koma::load::BuildLoadRequest(options);
  if (!request.ok()) return Fail(std::string(request.status().message()));
  const auto channels = koma::load::MakeChannels(*target, options.channels);
  if (!AllConnected(channels)) {
    return Fail(
        absl::StrCat("cannot connect to ", target->uri, " within ", kConnectTimeoutS, " s"));
  }

  koma::load::RunResult result = koma::load::RunLoad(options, *request, channels);
  koma::load::Report report = koma::load::Summarise(result);
  report.rpc = options.rpc;
  report.target = target->uri;
  report.request = request->description;
  report.request_bytes = static_cast<int64_t>(request->bytes.size());
  report.mode = Mode(options);

  if (!options.quiet) std::fputs(koma::load::ReportToText(report).c_str(), stdout);
  if (!options.json_path.empty()) {
    std::ofstream out(options.json_path, std::ios::trunc);
    if (!(out << koma::load::ReportToJson(report).dump(2) << '\n')) {
      return Fail(absl::StrCat("--json: cannot write ", options.json_path));
    }
  }
  if (options.fail_on_error && report.ok != report.count) return 1;
  return 0;
}

#include "server/page_routes.h"

#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>

#include "absl/strings/escaping.h"
#include "absl/strings/match.h"
#include "client/file_job.h"
#include "server/page_options.h"

namespace koma::server {
namespace {

// The assets, by URL path: the file in web/ and its type.
struct Asset {
  const char* path;
  const char* file;
  const char* type;
};
constexpr Asset kAssets[] = {
    {"/", "index.html", "text/html; charset=utf-8"},
    {"/page.css", "page.css", "text/css; charset=utf-8"},
    {"/page.js", "page.js", "text/javascript; charset=utf-8"},
    {"/page/report-frame.html", "report-frame.html", "text/html; charset=utf-8"},
};

HttpResponse JsonResponse(int status, const nlohmann::json& body) {
  HttpResponse response;
  response.status = status;
  response.SetHeader("Content-Type", "application/json");
  response.SetHeader("Cache-Control", "no-store");
  response.body = body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return response;
}

HttpResponse ErrorResponse(int status, const std::string& code, const std::string& message) {
  return JsonResponse(status, {{"error", {{"code", code}, {"message", message}}}});
}

// The HTTP status of a failed job: koma's error code (its --json error object) as the Connect
// protocol maps gRPC's; a usage error or a file koma cannot read is the request's fault (400).
int FailureStatus(const client::FileJobResult& result) {
  if (result.summary.is_object() && result.summary.contains("error")) {
    const std::string code = result.summary["error"].value("code", "");
    if (code == "RESOURCE_EXHAUSTED") return 429;
    if (code == "UNAVAILABLE") return 503;
    if (code == "DEADLINE_EXCEEDED") return 504;
    if (code == "INTERNAL" || code == "UNKNOWN" || code == "DATA_LOSS") return 500;
  }
  return 400;
}

// "koma skeletal pitch.bvh -o pitch_anime.bvh ..." with each word that a shell would split or
// expand in single quotes.
std::string ShellLine(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& word : words) {
    if (!line.empty()) line += ' ';
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789-_.,/=:+") == std::string::npos;
    if (plain) {
      line += word;
      continue;
    }
    line += '\'';
    for (char c : word) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

// Runs `work` on a thread of its own and waits: civetweb's threads have small stacks (koma_server
// overflowed one in a job's gRPC call), too small for the CLI's command, a gRPC call or the
// readers' recursion on a hostile file; a std::thread gets the process default (8 MiB). Joined
// at once, so civetweb's --http_threads still bound the jobs at a time.
template <typename Work>
void OnFullStack(Work work) {
  std::thread worker(work);
  worker.join();
}

HttpResponse Run(const HttpRequest& request, const std::shared_ptr<grpc::Channel>& channel) {
  absl::StatusOr<client::FileJob> job = PageJobFromQuery(request.query, request.body);
  if (!job.ok()) return ErrorResponse(400, "invalid_argument", std::string(job.status().message()));
  absl::StatusOr<client::FileJobResult> result = absl::InternalError("the job did not run");
  OnFullStack([&] { result = client::RunFileJob(*job, channel); });
  if (!result.ok()) return ErrorResponse(400, "invalid_argument", std::string(result.status().message()));
  nlohmann::json files = nlohmann::json::array();
  for (const client::FileJobFile& file : result->files) {
    files.push_back({{"role", file.role},
                     {"name", file.name},
                     {"bytes", file.bytes.size()},
                     {"base64", absl::Base64Escape(file.bytes)}});
  }
  const nlohmann::json body = {{"exit_code", result->exit_code},
                               {"command_line", result->command_line},
                               {"command", ShellLine(result->command_line)},
                               {"messages", result->messages},
                               {"summary", result->summary},
                               {"files", std::move(files)}};
  return JsonResponse(result->exit_code == 0 ? 200 : FailureStatus(*result), body);
}

HttpResponse Inspect(const HttpRequest& request) {
  absl::StatusOr<std::vector<std::pair<std::string, std::string>>> pairs =
      SplitQuery(request.query);
  if (!pairs.ok()) return ErrorResponse(400, "invalid_argument", std::string(pairs.status().message()));
  std::string name;
  for (const auto& [key, value] : *pairs) {
    if (key != "name") {
      return ErrorResponse(400, "invalid_argument", "unknown parameter \"" + key + "\"");
    }
    name = value;
  }
  nlohmann::json info;
  OnFullStack([&] { info = client::InspectFile(name, request.body); });
  return JsonResponse(200, info);
}

}  // namespace

void RegisterPageRoutes(HttpServer& http, std::shared_ptr<grpc::Channel> channel) {
  for (const Asset& asset : kAssets) {
    const std::string_view text = PageAsset(asset.file);
    const bool frame = absl::EndsWith(asset.path, "report-frame.html");
    http.Handle("GET", asset.path, [text, asset, frame](const HttpRequest&) {
      HttpResponse response;
      response.SetHeader("Content-Type", asset.type);
      response.SetHeader("Content-Security-Policy",
                         frame ? kReportFrameContentSecurityPolicy : kPageContentSecurityPolicy);
      response.body = std::string(text);
      return response;
    });
  }
  http.Handle("POST", "/page/inspect", [](const HttpRequest& request) { return Inspect(request); });
  http.Handle("POST", "/page/run", [channel = std::move(channel)](const HttpRequest& request) {
    return Run(request, channel);
  });
}

}  // namespace koma::server

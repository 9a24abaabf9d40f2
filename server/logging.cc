#include "server/logging.h"

#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <atomic>
#include <chrono>

#include "absl/strings/str_cat.h"
#include "core/split_mix64.h"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <ctime>
#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "server/status_mapping.h"

namespace koma::server {
namespace {

LogFormat g_format = LogFormat::kText;

// UTC time with milliseconds, ISO 8601: 2026-11-21T13:05:28.123Z.
std::string NowIso8601() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto millis =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() %
      1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%S", &utc);
  return absl::StrFormat("%s.%03dZ", buffer, static_cast<int>(millis));
}

void Emit(spdlog::level::level_enum level, nlohmann::json fields, std::string text) {
  if (g_format == LogFormat::kJson) {
    fields["ts"] = NowIso8601();
    fields["level"] = spdlog::level::to_string_view(level).data();
    // Invalid UTF-8 from a client (a peer string, a joint name) is replaced, not thrown.
    spdlog::log(level, "{}", fields.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    spdlog::log(level, "{}", text);
  }
}

}  // namespace

absl::Status ConfigureLogging(absl::string_view level, absl::string_view format) {
  const spdlog::level::level_enum parsed = spdlog::level::from_str(std::string(level));
  if (parsed == spdlog::level::off && level != "off") {
    return absl::InvalidArgumentError(absl::StrCat(
        "--log_level: \"", level, "\" (expected trace, debug, info, warn, error, critical, off)"));
  }
  if (format == "text") {
    g_format = LogFormat::kText;
  } else if (format == "json") {
    g_format = LogFormat::kJson;
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat("--log_format: \"", format, "\" (expected text or json)"));
  }
  auto logger = spdlog::stderr_logger_mt("koma");
  logger->set_level(parsed);
  logger->set_pattern(g_format == LogFormat::kJson ? "%v" : "%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  logger->flush_on(spdlog::level::trace);
  spdlog::set_default_logger(logger);
  return absl::OkStatus();
}

namespace {
spdlog::level::level_enum RpcLineLevel(const RpcRecord& r) {
  if (r.code == grpc::StatusCode::INTERNAL) return spdlog::level::err;
  return r.warnings.empty() ? spdlog::level::info : spdlog::level::warn;
}
}  // namespace

bool RpcLineLogged(const RpcRecord& record) {
  return spdlog::default_logger_raw()->should_log(RpcLineLevel(record));
}

void LogRpc(const RpcRecord& r) {
  const spdlog::level::level_enum level = RpcLineLevel(r);
  // Nothing is formatted for a line the level filters out, and only the chosen format is
  // built: this runs once per call.
  if (!spdlog::default_logger_raw()->should_log(level)) return;
  const std::string code = GrpcCodeName(r.code);
  if (g_format == LogFormat::kJson) {
    nlohmann::json fields = {{"msg", "rpc"},         {"method", r.method},
                             {"request_id", r.request_id},
                             {"peer", r.peer},       {"frames", r.frames},
                             {"joints", r.joints},   {"curves", r.curves},
                             {"bytes_in", r.bytes_in},
                             {"bytes_out", r.bytes_out}, {"code", code},
                             {"latency_ms", r.latency_ms}};
    if (r.code != grpc::StatusCode::OK) fields["error"] = r.error;
    if (!r.warnings.empty()) fields["warnings"] = r.warnings;
    Emit(level, std::move(fields), "");
    return;
  }
  std::string text = absl::StrFormat("rpc %s id=%s peer=%s frames=%d joints=%d curves=%d in=%dB "
                                     "out=%dB code=%s latency_ms=%.3f",
                                     r.method, r.request_id, r.peer, r.frames, r.joints,
                                     r.curves, r.bytes_in, r.bytes_out, code, r.latency_ms);
  if (r.code != grpc::StatusCode::OK) absl::StrAppend(&text, " error=\"", r.error, "\"");
  for (const std::string& warning : r.warnings) absl::StrAppend(&text, " warning=\"", warning, "\"");
  Emit(level, {}, std::move(text));
}

void LogEvent(absl::string_view message, bool warning) {
  Emit(warning ? spdlog::level::warn : spdlog::level::info, {{"msg", message}},
       std::string(message));
}

namespace {

constexpr absl::string_view kRequestIdKey = "x-request-id";
constexpr size_t kMaxRequestIdBytes = 128;

std::string NewOrGivenRequestId(const grpc::CallbackServerContext& context) {
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find(grpc::string_ref(kRequestIdKey.data(), kRequestIdKey.size()));
  if (found != metadata.end() && found->second.size() > 0) {
    return std::string(found->second.data(), std::min(found->second.size(), kMaxRequestIdBytes));
  }
  static std::atomic<uint64_t> counter{
      static_cast<uint64_t>(std::chrono::system_clock::now().time_since_epoch().count())};
  SplitMix64 rng(counter.fetch_add(1));
  return absl::StrCat(absl::Hex(rng.Next(), absl::kZeroPad16));
}

}  // namespace

std::string TakeRequestId(grpc::CallbackServerContext* context) {
  std::string id = NewOrGivenRequestId(*context);
  context->AddInitialMetadata(std::string(kRequestIdKey), id);
  return id;
}

}  // namespace koma::server

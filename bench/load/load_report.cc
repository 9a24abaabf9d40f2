#include "bench/load/load_report.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace koma::load {

double NearestRank(const std::vector<double>& sorted, double p) {
  const double n = static_cast<double>(sorted.size());
  const auto rank = static_cast<size_t>(std::ceil(p / 100.0 * n));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

Report Summarise(RunResult& result) {
  Report report;
  std::vector<double>& latencies = result.latencies_ms;
  std::sort(latencies.begin(), latencies.end());
  report.ok = static_cast<int64_t>(latencies.size());
  report.errors = result.errors;
  report.count = report.ok;
  for (const auto& [code, n] : report.errors) report.count += n;
  report.measured_s = result.measured_s;
  report.rps = result.measured_s > 0.0 ? report.count / result.measured_s : 0.0;
  report.warmup_calls = result.warmup_calls;
  report.hit_time_cap = result.hit_time_cap;
  report.response_bytes_min = result.response_bytes_min;
  report.response_bytes_max = result.response_bytes_max;
  report.ok_by_peer = result.ok_by_peer;
  if (latencies.empty()) return report;
  report.mean_ms = std::accumulate(latencies.begin(), latencies.end(), 0.0) / latencies.size();
  report.p50_ms = NearestRank(latencies, 50.0);
  report.p90_ms = NearestRank(latencies, 90.0);
  report.p99_ms = NearestRank(latencies, 99.0);
  report.p999_ms = NearestRank(latencies, 99.9);
  report.max_ms = latencies.back();
  return report;
}

nlohmann::json ReportToJson(const Report& r) {
  nlohmann::json errors = nlohmann::json::object();
  for (const auto& [code, n] : r.errors) errors[code] = n;
  nlohmann::json ok_by_peer = nlohmann::json::object();
  for (const auto& [peer, n] : r.ok_by_peer) ok_by_peer[peer] = n;
  return {
      {"rpc", r.rpc},
      {"target", r.target},
      {"request", r.request},
      {"request_bytes", r.request_bytes},
      {"response_bytes", {{"min", r.response_bytes_min}, {"max", r.response_bytes_max}}},
      {"mode", r.mode},
      {"count", r.count},
      {"ok", r.ok},
      {"measured_s", r.measured_s},
      {"rps", r.rps},
      {"latency_ms",
       {{"mean", r.mean_ms},
        {"p50", r.p50_ms},
        {"p90", r.p90_ms},
        {"p99", r.p99_ms},
        {"p99.9", r.p999_ms},
        {"max", r.max_ms}}},
      {"errors", errors},
      {"ok_by_peer", ok_by_peer},
      {"warmup_calls", r.warmup_calls},
      {"hit_time_cap", r.hit_time_cap},
  };
}

std::string ReportToText(const Report& r) {
  std::string out = absl::StrFormat(
      "Summary:\n  RPC:       %s\n  Target:    %s\n  Request:   %s, %d bytes\n"
      "  Response:  %d to %d bytes\n"
      "  Load:      %s\n  Count:     %d (%d ok, %d warmup calls not counted)\n"
      "  Total:     %.3f s\n  RPS:       %.2f\n",
      r.rpc, r.target, r.request, r.request_bytes, r.response_bytes_min, r.response_bytes_max,
      r.mode, r.count, r.ok, r.warmup_calls, r.measured_s, r.rps);
  if (r.hit_time_cap)
    absl::StrAppend(&out, "  Note:      stopped by --max-duration before --count\n");
  if (r.ok_by_peer.size() > 1) {
    absl::StrAppend(
        &out, "  Answered:  ", absl::StrJoin(r.ok_by_peer, ", ", absl::PairFormatter(" ")), "\n");
  }
  absl::StrAppend(&out, "\nLatency (ms, successful calls):\n");
  absl::StrAppend(
      &out, absl::StrFormat("  %-8s %10s\n  %-8s %10.3f\n  %-8s %10.3f\n  %-8s %10.3f\n"
                            "  %-8s %10.3f\n  %-8s %10.3f\n  %-8s %10.3f\n",
                            "", "ms", "mean", r.mean_ms, "p50", r.p50_ms, "p90", r.p90_ms, "p99",
                            r.p99_ms, "p99.9", r.p999_ms, "max", r.max_ms));
  absl::StrAppend(&out, "\nStatus code distribution:\n");
  absl::StrAppend(&out, absl::StrFormat("  [OK]  %d responses\n", r.ok));
  for (const auto& [code, n] : r.errors) {
    absl::StrAppend(&out, absl::StrFormat("  [%s]  %d responses\n", code, n));
  }
  return out;
}

}  // namespace koma::load

// koma_load's report, as ghz prints it: count, RPS, latency percentiles and errors by
// status code; a text table for people and JSON for scripts.
#ifndef KOMA_BENCH_LOAD_LOAD_REPORT_H_
#define KOMA_BENCH_LOAD_LOAD_REPORT_H_

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/load/load_runner.h"

namespace koma::load {

// The nearest-rank percentile p (0 < p <= 100) of `sorted` (ascending, non-empty): the
// value at 1-based rank ceil(p / 100 x n).
double NearestRank(const std::vector<double>& sorted, double p);

struct Report {
  std::string rpc;
  std::string target;
  std::string request;  // LoadRequest::description
  int64_t request_bytes = 0;
  int64_t response_bytes_min = 0, response_bytes_max = 0;  // of successful calls
  // Successful calls by the server that answered them ("ipv4:127.0.0.1:50051").
  std::map<std::string, int64_t> ok_by_peer;
  std::string mode;   // "closed (concurrency 4)" or "open (rate 100/s)"
  int64_t count = 0;  // measured calls, ok or not
  int64_t ok = 0;
  double measured_s = 0.0;
  double rps = 0.0;  // count / measured_s
  // Latency of successful calls, milliseconds (0 when there were none).
  double mean_ms = 0.0, p50_ms = 0.0, p90_ms = 0.0, p99_ms = 0.0, p999_ms = 0.0, max_ms = 0.0;
  std::map<std::string, int64_t> errors;
  int64_t warmup_calls = 0;
  bool hit_time_cap = false;
};

// Sorts result.latencies_ms in place and summarises it.
Report Summarise(RunResult& result);

nlohmann::json ReportToJson(const Report& report);
std::string ReportToText(const Report& report);

}  // namespace koma::load

#endif  // KOMA_BENCH_LOAD_LOAD_REPORT_H_

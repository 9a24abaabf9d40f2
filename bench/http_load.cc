// koma_http_load: koma_load's request (the same synthesis, bench/load/load_request.h) sent to
// koma_server's HTTP port in the Connect protocol's unary form, closed loop: `--concurrency`
// threads, each with one kept-alive connection (libcurl), for --warmup + --duration seconds.
// Prints one JSON line: {"rps":..,"p50_ms":..,"p99_ms":..,"calls":..,"errors":..}.
//   koma_http_load --url http://127.0.0.1:PORT --rpc skeletal --frames 129 --joints 31
//       --concurrency 4 --duration 5 --warmup 1 [--json-body]
// bench/http_load_pairs.sh runs it beside koma_load on the same server (docs/benchmarks.md).
#include <curl/curl.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "CLI/CLI.hpp"
#include "bench/load/load_options.h"
#include "bench/load/load_request.h"
#include "koma/v1/retime.pb.h"

namespace {

using Clock = std::chrono::steady_clock;

size_t Collect(char* data, size_t size, size_t count, void* out) {
  static_cast<std::string*>(out)->append(data, size * count);
  return size * count;
}

// The request as protobuf's JSON, or an empty string when it does not convert.
std::string AsJson(const koma::load::LoadRequest& request) {
  std::string json;
  const auto convert = [&](auto message) {
    if (message.ParseFromString(request.bytes)) {
      (void)google::protobuf::util::MessageToJsonString(message, &json);
    }
  };
  if (request.method == "/koma.v1.Retime/RetimeSkeletal") convert(koma::v1::RetimeSkeletalRequest());
  if (request.method == "/koma.v1.Retime/RetimeCurves") convert(koma::v1::RetimeCurvesRequest());
  if (request.method == "/koma.v1.Retime/LipBlink") convert(koma::v1::LipBlinkRequest());
  return json;
}

struct Worker {
  std::vector<double> latencies_ms;  // measured calls only
  int64_t errors = 0;
  std::string first_error;
};

}  // namespace

int main(int argc, char** argv) {
  koma::load::LoadOptions options;
  std::string url;
  bool json_body = false;
  double duration_s = 5.0;
  CLI::App app{"koma_http_load: koma_load's request over the HTTP port's Connect API"};
  app.add_option("--url", url, "the HTTP port, http://127.0.0.1:PORT")->required();
  app.add_option("--rpc", options.rpc, "skeletal, curves or lipblink")->required();
  app.add_option("--input", options.input, "the request's file (as koma_load --input)");
  app.add_option("--frames", options.frames, "synthetic frames");
  app.add_option("--joints", options.joints, "synthetic joints (skeletal)");
  app.add_option("--curves", options.curves, "synthetic curves");
  app.add_option("--concurrency,-c", options.concurrency, "threads, one connection each")
      ->check(CLI::Range(1, 256));
  app.add_option("--duration", duration_s, "measured seconds")->check(CLI::Range(0.1, 600.0));
  app.add_option("--warmup", options.warmup_s, "seconds left out of the statistics")
      ->check(CLI::Range(0.0, 60.0));
  app.add_flag("--json-body", json_body, "send application/json (else application/proto)");
  CLI11_PARSE(app, argc, argv);

  auto request = koma::load::BuildLoadRequest(options);
  if (!request.ok()) {
    std::fprintf(stderr, "koma_http_load: %s\n", std::string(request.status().message()).c_str());
    return 1;
  }
  const std::string body = json_body ? AsJson(*request) : request->bytes;
  if (body.empty() && json_body) {
    std::fprintf(stderr, "koma_http_load: the request does not convert to JSON\n");
    return 1;
  }
  const std::string endpoint = url + request->method;
  curl_global_init(CURL_GLOBAL_DEFAULT);
  const Clock::time_point start = Clock::now();
  const Clock::time_point measure_from = start + std::chrono::duration_cast<Clock::duration>(
                                                     std::chrono::duration<double>(options.warmup_s));
  const Clock::time_point end = measure_from + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(duration_s));
  std::vector<Worker> workers(static_cast<size_t>(options.concurrency));
  std::vector<std::thread> threads;
  for (Worker& worker : workers) {
    threads.emplace_back([&, w = &worker] {
      CURL* curl = curl_easy_init();
      curl_slist* headers = nullptr;
      headers = curl_slist_append(
          headers, json_body ? "Content-Type: application/json" : "Content-Type: application/proto");
      headers = curl_slist_append(headers, "Connect-Protocol-Version: 1");
      headers = curl_slist_append(headers, "Expect:");  // send the body at once
      std::string answer;
      curl_easy_setopt(curl, CURLOPT_URL, endpoint.c_str());
      curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
      curl_easy_setopt(curl, CURLOPT_POSTFIELDS, body.data());
      curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(body.size()));
      curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, Collect);
      curl_easy_setopt(curl, CURLOPT_WRITEDATA, &answer);
      curl_easy_setopt(curl, CURLOPT_TIMEOUT, 60L);
      curl_easy_setopt(curl, CURLOPT_TCP_NODELAY, 1L);
      while (true) {
        const Clock::time_point call_start = Clock::now();
        if (call_start >= end) break;
        answer.clear();
        const CURLcode result = curl_easy_perform(curl);
        long status = 0;
        curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &status);
        const Clock::time_point call_end = Clock::now();
        if (call_start < measure_from || call_end > end) continue;
        if (result != CURLE_OK || status != 200) {
          if (w->errors++ == 0) {
            w->first_error = result != CURLE_OK ? curl_easy_strerror(result) : answer.substr(0, 300);
          }
          continue;
        }
        w->latencies_ms.push_back(
            std::chrono::duration<double, std::milli>(call_end - call_start).count());
      }
      curl_slist_free_all(headers);
      curl_easy_cleanup(curl);
    });
  }
  for (std::thread& thread : threads) thread.join();
  curl_global_cleanup();
  std::vector<double> all;
  int64_t errors = 0;
  for (const Worker& worker : workers) {
    all.insert(all.end(), worker.latencies_ms.begin(), worker.latencies_ms.end());
    errors += worker.errors;
    if (worker.errors > 0) std::fprintf(stderr, "koma_http_load: %s\n", worker.first_error.c_str());
  }
  std::sort(all.begin(), all.end());
  const auto quantile = [&](double q) {
    return all.empty() ? 0.0 : all[std::min(all.size() - 1, static_cast<size_t>(q * all.size()))];
  };
  std::printf("{\"rps\":%.1f,\"p50_ms\":%.3f,\"p99_ms\":%.3f,\"calls\":%zu,\"errors\":%lld,"
              "\"body_bytes\":%zu}\n",
              static_cast<double>(all.size()) / duration_s, quantile(0.5), quantile(0.99),
              all.size(), static_cast<long long>(errors), body.size());
  return errors > 0 ? 1 : 0;
}

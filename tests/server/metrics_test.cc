// RpcMetrics on a registry read back with Collect() and the text serializer, the service
// counting real calls through an in-process channel, and the /metrics endpoint's address
// checks.
#include "server/metrics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "koma/v1/retime.grpc.pb.h"
#include "server/metrics_endpoint.h"
#include "server/server.h"
#include "tests/server/in_process_server.h"
#include "tests/server/request_builder.h"

namespace koma::server {
namespace {

using ::koma::testing::CallRpc;

using ::testing::HasSubstr;
using ::testing::SizeIs;

// The series of family `name` whose labels include every pair of `labels` (a pointer into
// `families`); fails the test unless there is exactly one.
const prometheus::ClientMetric* Find(const std::vector<prometheus::MetricFamily>& families,
                                     const std::string& name,
                                     const std::map<std::string, std::string>& labels) {
  const prometheus::ClientMetric* found = nullptr;
  int matches = 0;
  for (const prometheus::MetricFamily& family : families) {
    if (family.name != name) continue;
    for (const prometheus::ClientMetric& metric : family.metric) {
      int matched = 0;
      for (const auto& label : metric.label) {
        const auto it = labels.find(label.name);
        if (it != labels.end() && it->second == label.value) ++matched;
      }
      if (matched == static_cast<int>(labels.size())) {
        found = &metric;
        ++matches;
      }
    }
  }
  EXPECT_EQ(matches, 1) << name;
  return found;
}

double Counter(const prometheus::Registry& registry, const std::string& name,
               const std::map<std::string, std::string>& labels) {
  const std::vector<prometheus::MetricFamily> families = registry.Collect();
  const prometheus::ClientMetric* metric = Find(families, name, labels);
  return metric == nullptr ? -1 : metric->counter.value;
}

double Handled(const prometheus::Registry& registry, const std::string& method,
               const std::string& code) {
  return Counter(registry, "grpc_server_handled_total",
                 {{"grpc_method", method}, {"grpc_code", code}});
}

double InFlight(const prometheus::Registry& registry) {
  const std::vector<prometheus::MetricFamily> families = registry.Collect();
  const prometheus::ClientMetric* metric = Find(families, "koma_requests_in_flight", {});
  return metric == nullptr ? -1 : metric->gauge.value;
}

size_t SeriesCount(const prometheus::Registry& registry, const std::string& name) {
  for (const prometheus::MetricFamily& family : registry.Collect()) {
    if (family.name == name) return family.metric.size();
  }
  return 0;
}

TEST(RpcMetricsTest, CreatesEverySeriesAtZero) {
  prometheus::Registry registry;
  RpcMetrics metrics(registry);
  EXPECT_EQ(SeriesCount(registry, "grpc_server_started_total"), 3u);
  EXPECT_EQ(SeriesCount(registry, "grpc_server_handled_total"), 3u * 17u);
  EXPECT_EQ(SeriesCount(registry, "grpc_server_handling_seconds"), 3u);
  EXPECT_EQ(SeriesCount(registry, "koma_frames_processed_total"), 3u);
  EXPECT_EQ(SeriesCount(registry, "koma_request_bytes_total"), 3u);
  EXPECT_EQ(SeriesCount(registry, "koma_response_bytes_total"), 3u);
  EXPECT_EQ(SeriesCount(registry, "koma_requests_in_flight"), 1u);
  EXPECT_EQ(Handled(registry, "LipBlink", "UNAUTHENTICATED"), 0.0);
  EXPECT_EQ(Handled(registry, "RetimeCurves", "OK"), 0.0);
  EXPECT_EQ(InFlight(registry), 0.0);
}

TEST(RpcMetricsTest, CountsPerMethodAndCode) {
  prometheus::Registry registry;
  RpcMetrics metrics(registry);
  const CallMetrics& skeletal = metrics.ForMethod(RpcMethod::kRetimeSkeletal);
  const CallMetrics& lip_blink = metrics.ForMethod(RpcMethod::kLipBlink);
  for (int i = 0; i < 3; ++i) skeletal.Start();
  lip_blink.Start();
  EXPECT_EQ(InFlight(registry), 4.0);
  skeletal.Finish(grpc::StatusCode::OK, 0.001, 130, 1000, 2000);
  skeletal.Finish(grpc::StatusCode::OK, 0.002, 130, 1000, 2000);
  skeletal.Finish(grpc::StatusCode::RESOURCE_EXHAUSTED, 0.0001, 130, 500, 0);
  lip_blink.Finish(grpc::StatusCode::INVALID_ARGUMENT, 0.0001, 121, 300, 0);

  EXPECT_EQ(InFlight(registry), 0.0);
  EXPECT_EQ(Counter(registry, "grpc_server_started_total",
                    {{"grpc_method", "RetimeSkeletal"},
                     {"grpc_service", "koma.v1.Retime"},
                     {"grpc_type", "unary"}}),
            3.0);
  EXPECT_EQ(Counter(registry, "grpc_server_started_total", {{"grpc_method", "LipBlink"}}), 1.0);
  EXPECT_EQ(Counter(registry, "grpc_server_started_total", {{"grpc_method", "RetimeCurves"}}), 0.0);
  EXPECT_EQ(Handled(registry, "RetimeSkeletal", "OK"), 2.0);
  EXPECT_EQ(Handled(registry, "RetimeSkeletal", "RESOURCE_EXHAUSTED"), 1.0);
  EXPECT_EQ(Handled(registry, "RetimeSkeletal", "INVALID_ARGUMENT"), 0.0);
  EXPECT_EQ(Handled(registry, "LipBlink", "INVALID_ARGUMENT"), 1.0);
  EXPECT_EQ(Handled(registry, "LipBlink", "OK"), 0.0);
  // Frames and response bytes only from the calls that ended OK; request bytes from all.
  EXPECT_EQ(Counter(registry, "koma_frames_processed_total", {{"grpc_method", "RetimeSkeletal"}}),
            260.0);
  EXPECT_EQ(Counter(registry, "koma_frames_processed_total", {{"grpc_method", "LipBlink"}}), 0.0);
  EXPECT_EQ(Counter(registry, "koma_request_bytes_total", {{"grpc_method", "RetimeSkeletal"}}),
            2500.0);
  EXPECT_EQ(Counter(registry, "koma_response_bytes_total", {{"grpc_method", "RetimeSkeletal"}}),
            4000.0);
  EXPECT_EQ(Counter(registry, "koma_request_bytes_total", {{"grpc_method", "LipBlink"}}), 300.0);
}

TEST(RpcMetricsTest, HistogramCountsSumsAndBuckets) {
  prometheus::Registry registry;
  RpcMetrics metrics(registry);
  const CallMetrics& curves = metrics.ForMethod(RpcMethod::kRetimeCurves);
  for (double seconds : {0.0003, 0.002, 0.002, 45.0}) {
    curves.Start();
    curves.Finish(grpc::StatusCode::OK, seconds, 10, 1, 1);
  }
  const std::vector<prometheus::MetricFamily> families = registry.Collect();
  const prometheus::ClientMetric* metric =
      Find(families, "grpc_server_handling_seconds", {{"grpc_method", "RetimeCurves"}});
  ASSERT_NE(metric, nullptr);
  const prometheus::ClientMetric::Histogram& h = metric->histogram;
  EXPECT_EQ(h.sample_count, 4u);
  EXPECT_DOUBLE_EQ(h.sample_sum, 0.0003 + 0.002 + 0.002 + 45.0);
  ASSERT_THAT(h.bucket, SizeIs(kHandlingSecondsBuckets.size() + 1));  // + the +Inf bucket
  EXPECT_EQ(h.bucket[0].upper_bound, 0.0005);
  EXPECT_EQ(h.bucket[0].cumulative_count, 1u);
  EXPECT_EQ(h.bucket[2].upper_bound, 0.0025);
  EXPECT_EQ(h.bucket[2].cumulative_count, 3u);
  EXPECT_EQ(h.bucket[14].upper_bound, 30.0);
  EXPECT_EQ(h.bucket[14].cumulative_count, 3u);
  EXPECT_EQ(h.bucket[15].cumulative_count, 4u);  // 45 s only in +Inf
}

TEST(RpcMetricsTest, TextExpositionHasTheConventionalNames) {
  prometheus::Registry registry;
  RpcMetrics metrics(registry);
  const CallMetrics& lip_blink = metrics.ForMethod(RpcMethod::kLipBlink);
  lip_blink.Start();
  lip_blink.Finish(grpc::StatusCode::INVALID_ARGUMENT, 0.001, 0, 7, 0);
  const std::string text = prometheus::TextSerializer().Serialize(registry.Collect());
  EXPECT_THAT(text, HasSubstr("# TYPE grpc_server_handled_total counter\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE grpc_server_handling_seconds histogram\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE koma_requests_in_flight gauge\n"));
  EXPECT_THAT(text, HasSubstr("grpc_server_handled_total{grpc_code=\"INVALID_ARGUMENT\","
                              "grpc_method=\"LipBlink\",grpc_service=\"koma.v1.Retime\","
                              "grpc_type=\"unary\"} 1\n"));
  EXPECT_THAT(text, HasSubstr("grpc_server_handling_seconds_count{grpc_method=\"LipBlink\","
                              "grpc_service=\"koma.v1.Retime\",grpc_type=\"unary\"} 1\n"));
  EXPECT_THAT(text, HasSubstr("koma_request_bytes_total{grpc_method=\"LipBlink\"} 7\n"));
  EXPECT_THAT(text, HasSubstr("koma_requests_in_flight 0\n"));
}

std::unique_ptr<KomaServer> StartInProcess(std::shared_ptr<prometheus::Registry> registry) {
  ServerConfig config;
  config.address = "";
  config.worker_threads = 2;
  config.metrics_registry = std::move(registry);
  return KomaServer::Start(config).value();
}

TEST(ServiceMetricsTest, CountsEveryCallOfTheService) {
  auto registry = std::make_shared<prometheus::Registry>();
  auto server = StartInProcess(registry);
  auto stub = v1::Retime::NewStub(server->InProcessChannel());
  const v1::RetimeSkeletalRequest good = koma::testing::MakeSkeletalRequest(30);
  v1::RetimeSkeletalRequest bad = good;
  bad.mutable_motion()->mutable_channels()->mutable_values()->RemoveLast();
  double response_bytes = 0;
  for (int i = 0; i < 2; ++i) {
    v1::RetimeSkeletalResponse response;
    ASSERT_TRUE(CallRpc(*stub, good, &response).ok());
    response_bytes += static_cast<double>(response.ByteSizeLong());
  }
  v1::RetimeSkeletalResponse response;
  EXPECT_EQ(CallRpc(*stub, bad, &response).error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  // The metrics are updated before Finish, so they are complete when the client returns.
  const std::map<std::string, std::string> skeletal = {{"grpc_method", "RetimeSkeletal"}};
  EXPECT_EQ(Counter(*registry, "grpc_server_started_total", skeletal), 3.0);
  EXPECT_EQ(Handled(*registry, "RetimeSkeletal", "OK"), 2.0);
  EXPECT_EQ(Handled(*registry, "RetimeSkeletal", "INVALID_ARGUMENT"), 1.0);
  EXPECT_EQ(Counter(*registry, "koma_frames_processed_total", skeletal), 60.0);
  EXPECT_EQ(Counter(*registry, "koma_request_bytes_total", skeletal),
            2.0 * good.ByteSizeLong() + bad.ByteSizeLong());
  EXPECT_EQ(Counter(*registry, "koma_response_bytes_total", skeletal), response_bytes);
  EXPECT_EQ(InFlight(*registry), 0.0);
  const std::vector<prometheus::MetricFamily> families = registry->Collect();
  const prometheus::ClientMetric* latency =
      Find(families, "grpc_server_handling_seconds", skeletal);
  ASSERT_NE(latency, nullptr);
  EXPECT_EQ(latency->histogram.sample_count, 3u);
  EXPECT_GT(latency->histogram.sample_sum, 0.0);
}

TEST(ServiceMetricsTest, MetricsDoNotChangeTheResponseBytes) {
  auto with = StartInProcess(std::make_shared<prometheus::Registry>());
  auto without = StartInProcess(nullptr);
  const v1::RetimeSkeletalRequest request = koma::testing::MakeSkeletalRequest(40);
  v1::RetimeSkeletalResponse a, b;
  ASSERT_TRUE(CallRpc(*v1::Retime::NewStub(with->InProcessChannel()), request, &a).ok());
  ASSERT_TRUE(CallRpc(*v1::Retime::NewStub(without->InProcessChannel()), request, &b).ok());
  EXPECT_EQ(a.SerializeAsString(), b.SerializeAsString());
}

TEST(MetricsEndpointTest, RejectsWhatIsNotHostPort) {
  auto registry = std::make_shared<prometheus::Registry>();
  for (const char* address : {"", "9464", "127.0.0.1", "127.0.0.1:", ":9464", "127.0.0.1:95s",
                              "127.0.0.1:65536", "127.0.0.1:1,127.0.0.1:2", "127.0.0.1:+80"}) {
    const auto endpoint = MetricsEndpoint::Start(address, registry);
    ASSERT_FALSE(endpoint.ok()) << address;
    EXPECT_EQ(endpoint.status().code(), absl::StatusCode::kInvalidArgument) << address;
    EXPECT_THAT(std::string(endpoint.status().message()),
                HasSubstr(std::string("--metrics_address: \"") + address + "\""));
  }
}

TEST(MetricsEndpointTest, BindsAFreeLoopbackPortAndRefusesABusyOne) {
  auto registry = std::make_shared<prometheus::Registry>();
  const auto first = MetricsEndpoint::Start("127.0.0.1:0", registry);
  ASSERT_TRUE(first.ok()) << first.status();
  const int port = (*first)->port();
  EXPECT_GT(port, 0);
  const std::string busy = "127.0.0.1:" + std::to_string(port);
  const auto second = MetricsEndpoint::Start(busy, registry);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(second.status().message()),
              HasSubstr("--metrics_address: could not listen on " + busy));
}

TEST(MetricsEndpointTest, ServerStartFailsCleanlyOnABadAddress) {
  ServerConfig config;
  config.address = "";
  config.metrics_address = "localhost";
  const auto server = KomaServer::Start(config);
  ASSERT_FALSE(server.ok());
  EXPECT_THAT(std::string(server.status().message()), HasSubstr("--metrics_address"));
}

}  // namespace
}  // namespace koma::server

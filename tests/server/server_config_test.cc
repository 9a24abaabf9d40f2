// KomaServer::Start refuses settings out of range before it binds anything, naming the
// koma_server flag and the value (ValidateServerConfig).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "server/server.h"

namespace koma::server {
namespace {

using ::testing::HasSubstr;

struct BadSetting {
  std::string name;
  std::function<void(ServerConfig&)> mutate;
  std::string message;
};

ServerConfig InProcessOnly() {
  ServerConfig config;
  config.address = "";  // no port: nothing to bind, so only the checks can fail
  return config;
}

TEST(ServerConfigTest, TheDefaultsAreValidAndStart) {
  EXPECT_TRUE(ValidateServerConfig(InProcessOnly()).ok());
  EXPECT_TRUE(KomaServer::Start(InProcessOnly()).ok());
}

TEST(ServerConfigTest, ZeroMeansNoneOrAutomaticWhereTheFlagSaysSo) {
  ServerConfig config = InProcessOnly();
  config.worker_threads = 0;                // one per core
  config.max_queued = 0;                    // no request waits
  config.inline_max_bytes = 0;              // every request on a worker
  config.idle_trim = absl::ZeroDuration();  // never trim
  config.idle_trim_min_request_bytes = 0;
  EXPECT_TRUE(ValidateServerConfig(config).ok()) << ValidateServerConfig(config);
  config.limits.max_values = 1;
  config.limits.max_joints = 1;
  config.limits.threads_per_call = 1;
  config.max_message_bytes = 1024;
  EXPECT_TRUE(ValidateServerConfig(config).ok()) << ValidateServerConfig(config);
}

TEST(ServerConfigTest, OutOfRangeSettingsAreRefusedByFlagAndValue) {
  const BadSetting kBad[] = {
      {"max_message_bytes", [](ServerConfig& c) { c.max_message_bytes = 1023; },
       "--max_message_bytes: 1023 is below 1024"},
      {"max_values zero", [](ServerConfig& c) { c.limits.max_values = 0; },
       "--max_values: 0 must be >= 1"},
      {"max_values negative", [](ServerConfig& c) { c.limits.max_values = -7; },
       "--max_values: -7 must be >= 1"},
      {"max_joints", [](ServerConfig& c) { c.limits.max_joints = -3; },
       "--max_joints: -3 must be >= 1"},
      {"threads_per_call", [](ServerConfig& c) { c.limits.threads_per_call = 0; },
       "limits.threads_per_call: 0 must be >= 1"},
      {"max_queued", [](ServerConfig& c) { c.max_queued = -5; },
       "--max_queued: -5 must be >= 0 (0 = no request waits)"},
      {"worker_threads", [](ServerConfig& c) { c.worker_threads = -1; },
       "--worker_threads: -1 must be >= 0 (0 = one per core)"},
      {"idle_trim", [](ServerConfig& c) { c.idle_trim = absl::Milliseconds(-1); },
       "--idle_trim_ms: -1 must be >= 0"},
      {"idle_trim_min_request_bytes", [](ServerConfig& c) { c.idle_trim_min_request_bytes = -5; },
       "idle_trim_min_request_bytes: -5 must be >= 0"},
      {"inline_max_bytes", [](ServerConfig& c) { c.inline_max_bytes = -1; },
       "--inline_max_bytes: -1 must be >= 0"},
      {"tls_cert without key", [](ServerConfig& c) { c.tls_cert_pem = "x"; },
       "--tls_cert and --tls_key: give both or neither"},
      {"tls_client_ca without cert", [](ServerConfig& c) { c.tls_client_ca_pem = "x"; },
       "--tls_client_ca needs --tls_cert and --tls_key"},
  };
  for (const BadSetting& bad : kBad) {
    ServerConfig config = InProcessOnly();
    bad.mutate(config);
    const auto server = KomaServer::Start(config);
    ASSERT_FALSE(server.ok()) << bad.name;
    EXPECT_EQ(server.status().code(), absl::StatusCode::kInvalidArgument) << bad.name;
    EXPECT_THAT(std::string(server.status().message()), HasSubstr(bad.message)) << bad.name;
  }
}

}  // namespace
}  // namespace koma::server

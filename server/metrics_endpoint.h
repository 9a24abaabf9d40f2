// The Prometheus scrape endpoint: plain HTTP GET /metrics on its own port (prometheus-cpp's
// Exposer, civetweb underneath, 2 threads), separate from the gRPC port so a scraper needs
// no gRPC, no TLS and no client certificate.
#ifndef KOMA_SERVER_METRICS_ENDPOINT_H_
#define KOMA_SERVER_METRICS_ENDPOINT_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace prometheus {
class Exposer;
class Registry;
}  // namespace prometheus

namespace koma::server {

class MetricsEndpoint {
 public:
  // Serves `registry` at http://`address`/metrics. `address` is HOST:PORT with a numeric
  // port (0 picks a free one), e.g. "127.0.0.1:9464" or "0.0.0.0:9464". INVALID_ARGUMENT or
  // UNAVAILABLE naming --metrics_address and the value when it is malformed or cannot be
  // bound.
  static absl::StatusOr<std::unique_ptr<MetricsEndpoint>> Start(
      const std::string& address, const std::shared_ptr<prometheus::Registry>& registry);
  ~MetricsEndpoint();

  MetricsEndpoint(const MetricsEndpoint&) = delete;
  MetricsEndpoint& operator=(const MetricsEndpoint&) = delete;

  // The bound port (the chosen one when the address asked for port 0).
  int port() const { return port_; }

 private:
  MetricsEndpoint() = default;

  std::unique_ptr<prometheus::Exposer> exposer_;
  int port_ = 0;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_METRICS_ENDPOINT_H_

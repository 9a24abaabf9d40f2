#include "server/metrics_endpoint.h"

#include <prometheus/exposer.h>
#include <prometheus/registry.h>

#include <exception>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"

namespace koma::server {
namespace {

// civetweb's listening_ports option accepts more than HOST:PORT ("9464" alone binds every
// interface, "9464s" is TLS, a comma makes a list). Only HOST:PORT with a decimal port in
// 0..65535 is let through, so the flag means what it says.
absl::Status CheckHostPort(absl::string_view address) {
  const size_t colon = address.rfind(':');
  const absl::string_view host =
      colon == absl::string_view::npos ? absl::string_view() : address.substr(0, colon);
  const absl::string_view port =
      colon == absl::string_view::npos ? absl::string_view() : address.substr(colon + 1);
  bool ok = !host.empty() && !port.empty() && port.size() <= 5;
  for (char c : host) ok = ok && c != ',' && !absl::ascii_isspace(static_cast<unsigned char>(c));
  int value = 0;
  for (char c : port) {
    ok = ok && absl::ascii_isdigit(static_cast<unsigned char>(c));
    value = value * 10 + (c - '0');
  }
  if (!ok || value > 65535) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--metrics_address: \"", address,
        "\" is not HOST:PORT with a port in 0..65535 (e.g. 127.0.0.1:9464, 0.0.0.0:9464)"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::unique_ptr<MetricsEndpoint>> MetricsEndpoint::Start(
    const std::string& address, const std::shared_ptr<prometheus::Registry>& registry) {
  if (absl::Status s = CheckHostPort(address); !s.ok()) return s;
  std::unique_ptr<MetricsEndpoint> endpoint(new MetricsEndpoint());
  try {
    // Two civetweb threads: scrapes are rare (every 15-60 s) and cheap.
    endpoint->exposer_ = std::make_unique<prometheus::Exposer>(address, 2);
  } catch (const std::exception&) {
    // civetweb reports every failure the same way ("null context ..."); say what it means.
    return absl::UnavailableError(
        absl::StrCat("--metrics_address: could not listen on ", address,
                     " (in use, an unknown host, or not an IPv4 address of this machine)"));
  }
  endpoint->exposer_->RegisterCollectable(registry);
  const std::vector<int> ports = endpoint->exposer_->GetListeningPorts();
  endpoint->port_ = ports.empty() ? 0 : ports.front();
  return endpoint;
}

MetricsEndpoint::~MetricsEndpoint() = default;

}  // namespace koma::server

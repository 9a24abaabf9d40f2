// koma_server's optional HTTP port (--http_port): a civetweb server that serves only the routes
// registered on it, through a plain request/response struct, so route code never touches
// civetweb. It carries the Connect JSON API (server/connect_api.h) and the page.
//
// The attack-surface rules live here, once for every route (docs/operations.md, "The HTTP
// port"): a request body over --http_max_body_bytes is answered 413 without being read; reading
// a request is bounded by --http_request_timeout_ms; only registered paths answer (404 otherwise:
// no document root, no file-system path is ever opened); no CORS header unless
// --http_cors_origin names an origin; every response carries a strict Content-Security-Policy
// and the other security headers (SecurityHeaders below).
#ifndef KOMA_SERVER_HTTP_SERVER_H_
#define KOMA_SERVER_HTTP_SERVER_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <shared_mutex>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

struct mg_context;
struct mg_connection;

namespace koma::server {

struct HttpServerConfig {
  // Where to listen: a numeric IPv4 address (--http_address). Loopback by default: the port
  // is opt-in, and reaching it from elsewhere is a deliberate choice (0.0.0.0 in a container).
  std::string address = "127.0.0.1";
  // --http_port: -1 = no HTTP port (the default), 0 = a free port (see port()), else the port.
  int port = -1;
  // Largest request body, bytes (--http_max_body_bytes); larger ones get 413 unread.
  int64_t max_body_bytes = 64 * 1024 * 1024;
  // Longest the server waits for a request's headers and for each read of its body, and for
  // the whole body, milliseconds (--http_request_timeout_ms): a client that sends slowly is cut
  // off (408) instead of holding a thread.
  int request_timeout_ms = 30'000;
  // Connections served at once (--http_threads): each holds one civetweb thread while its
  // request arrives and its call runs, and while it is kept alive idle (keep_alive_ms);
  // further connections wait in the listen queue. A browser opens up to 6 at once.
  int threads = 8;
  // How long a connection may stay open idle for its next request, milliseconds
  // (--http_keep_alive_ms); 0 = one request per connection.
  int keep_alive_ms = 1000;
  // The one origin allowed to call from a browser page elsewhere (--http_cors_origin), e.g.
  // "https://tools.example.com"; empty = no CORS headers at all (same-origin only).
  std::string cors_origin;
};

// InvalidArgument naming the first --http_* flag out of range and its value.
absl::Status ValidateHttpServerConfig(const HttpServerConfig& config);

struct HttpRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // URL-decoded, no query: "/koma.v1.Retime/LipBlink"
  std::string query;   // after '?', undecoded; empty without one
  // Header names lower-cased, values as sent, in the order sent.
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  std::string remote_address;  // the peer's IP address

  // The first header named `lower_case_name`; null without one.
  const std::string* Header(absl::string_view lower_case_name) const;
};

struct HttpResponse {
  int status = 200;
  // Sent as they are, after the server's security headers; a handler that sets its own
  // Content-Security-Policy (a page that needs its scripts) replaces the default one.
  // Content-Length is the server's.
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;

  void SetHeader(std::string name, std::string value) {
    headers.emplace_back(std::move(name), std::move(value));
  }
};

// An error as the Connect protocol writes one, whatever the route: HTTP `status`,
// application/json, {"code":"<code>","message":"<message>"}. The server's own refusals use it
// (404 not_found, 405 unimplemented, 408 deadline_exceeded, 413 resource_exhausted), so a
// client reads every error of the port the same way.
HttpResponse JsonError(int status, absl::string_view code, absl::string_view message);

// Runs on one of civetweb's threads; may block (each request has its thread). Must not throw.
using HttpHandler = std::function<HttpResponse(const HttpRequest&)>;

// The Content-Security-Policy of every response unless its handler sets another: nothing may
// load, run, embed or be embedded (an API answer is data, never a document).
inline constexpr char kDefaultContentSecurityPolicy[] =
    "default-src 'none'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'";

class HttpServer {
 public:
  // Listens on config.address:config.port (which must not be -1). UNAVAILABLE naming
  // --http_address/--http_port when it cannot.
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(const HttpServerConfig& config);
  // Stops listening and waits for the requests being served.
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // `method` requests to exactly `path` go to `handler`. Routes may be added at any time,
  // also while serving; a later registration of the same method and path replaces the earlier.
  void Handle(std::string method, std::string path, HttpHandler handler);
  // `method` requests to any path that starts with `prefix` and has no exact route; the
  // longest prefix wins. (The Connect API answers an unknown method of its service this way.)
  void HandlePrefix(std::string method, std::string prefix, HttpHandler handler);

  // The bound port (the chosen one when the config asked for port 0).
  int port() const { return port_; }
  const HttpServerConfig& config() const { return config_; }

  // Routing (for tests): the response the server would send to `request` (its body already
  // read), security and CORS headers included; what the civetweb callback sends.
  HttpResponse Respond(const HttpRequest& request) const;

 private:
  struct Route {
    std::string method;
    std::string path;
    bool prefix;
    HttpHandler handler;
  };
  explicit HttpServer(HttpServerConfig config) : config_(std::move(config)) {}
  static int OnRequest(mg_connection* connection, void* self);
  void AddRoute(Route route);
  HttpResponse Route404or405(const HttpRequest& request) const;
  void AddCommonHeaders(const HttpRequest& request, HttpResponse& response) const;

  const HttpServerConfig config_;
  mutable std::shared_mutex routes_mutex_;
  std::vector<Route> routes_;
  mg_context* context_ = nullptr;
  int port_ = 0;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_HTTP_SERVER_H_

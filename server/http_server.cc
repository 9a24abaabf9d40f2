#include "server/http_server.h"

#include <arpa/inet.h>
#include <civetweb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/strip.h"

namespace koma::server {
namespace {

using Clock = std::chrono::steady_clock;

// Headers on every response. nosniff: a browser never guesses a type (an API answer is never
// run as a script or a page); no-referrer: the page's URL (it may hold a file name) goes
// nowhere; same-origin resource and
// opener policies: no other origin reads the answers through <script>/<img> or a window.
constexpr std::pair<const char*, const char*> kSecurityHeaders[] = {
    {"X-Content-Type-Options", "nosniff"},
    {"Referrer-Policy", "no-referrer"},
    {"Cross-Origin-Resource-Policy", "same-origin"},
    {"Cross-Origin-Opener-Policy", "same-origin"},
};

// The request headers a cross-origin page may send (Connect's, and the request id).
constexpr char kCorsAllowHeaders[] =
    "Content-Type, Connect-Protocol-Version, Connect-Timeout-Ms, X-Request-Id";

bool IsCorsOrigin(absl::string_view origin) {
  if (origin == "*") return true;
  absl::string_view rest = origin;
  if (!absl::ConsumePrefix(&rest, "https://") && !absl::ConsumePrefix(&rest, "http://")) {
    return false;
  }
  if (rest.empty()) return false;
  for (char c : rest) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (!(absl::ascii_isalnum(u) || c == '.' || c == '-' || c == ':' || c == '[' || c == ']')) {
      return false;
    }
  }
  return true;
}

// Writes `response`; civetweb adds the status line, Date and Connection. After an interim
// 100 Continue (`continued`) civetweb counts its header as sent and would send none, so the
// status line and headers are written here, and the connection closes after the response.
void Send(mg_connection* connection, const HttpResponse& response, bool continued = false) {
  const std::string length = absl::StrCat(response.body.size());
  if (continued) {
    std::string head = absl::StrCat("HTTP/1.1 ", response.status, " ",
                                    mg_get_response_code_text(connection, response.status), "\r\n");
    for (const auto& [name, value] : response.headers) {
      if (absl::EqualsIgnoreCase(name, "Connection")) continue;
      absl::StrAppend(&head, name, ": ", value, "\r\n");
    }
    absl::StrAppend(&head, "Content-Length: ", length, "\r\nConnection: close\r\n\r\n");
    mg_write(connection, head.data(), head.size());
  } else {
    mg_response_header_start(connection, response.status);
    for (const auto& [name, value] : response.headers) {
      mg_response_header_add(connection, name.c_str(), value.c_str(), -1);
    }
    mg_response_header_add(connection, "Content-Length", length.c_str(), -1);
    mg_response_header_send(connection);
  }
  size_t sent = 0;
  while (sent < response.body.size()) {
    const int n = mg_write(connection, response.body.data() + sent, response.body.size() - sent);
    if (n <= 0) return;  // the client went away
    sent += static_cast<size_t>(n);
  }
}

// Silences civetweb's own stderr lines (a client that disconnects is not the server's error).
int QuietLog(const mg_connection*, const char*) { return 1; }

}  // namespace

absl::Status ValidateHttpServerConfig(const HttpServerConfig& config) {
  const auto invalid = [](auto&&... parts) {
    return absl::InvalidArgumentError(absl::StrCat(parts...));
  };
  if (config.port < -1 || config.port > 65535) {
    return invalid("--http_port: ", config.port,
                   " must be in [-1, 65535] (-1 = no HTTP port, 0 = a free port)");
  }
  if (config.address.empty() ||
      config.address.find_first_of(", \t\r\n") != std::string::npos) {
    return invalid("--http_address: \"", config.address,
                   "\" is not one address (e.g. 127.0.0.1, or 0.0.0.0 in a container)");
  }
  if (config.max_body_bytes < 1024) {
    return invalid("--http_max_body_bytes: ", config.max_body_bytes, " must be >= 1024");
  }
  if (config.request_timeout_ms < 100) {
    return invalid("--http_request_timeout_ms: ", config.request_timeout_ms, " must be >= 100");
  }
  if (config.keep_alive_ms < 0 || config.keep_alive_ms > 600'000) {
    return invalid("--http_keep_alive_ms: ", config.keep_alive_ms,
                   " must be in [0, 600000] (0 = one request per connection)");
  }
  if (config.threads < 1 || config.threads > 1024) {
    return invalid("--http_threads: ", config.threads, " must be in [1, 1024]");
  }
  if (!config.cors_origin.empty() && !IsCorsOrigin(config.cors_origin)) {
    return invalid("--http_cors_origin: \"", config.cors_origin,
                   "\" is not an origin (scheme://host[:port], no path, e.g. "
                   "https://tools.example.com) or *");
  }
  return absl::OkStatus();
}

HttpResponse JsonError(int status, absl::string_view code, absl::string_view message) {
  HttpResponse response;
  response.status = status;
  response.SetHeader("Content-Type", "application/json");
  const nlohmann::json error = {{"code", std::string(code)}, {"message", std::string(message)}};
  // A message quoting bytes that are not UTF-8 gets U+FFFD for them rather than a throw.
  response.body = error.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return response;
}

const std::string* HttpRequest::Header(absl::string_view lower_case_name) const {
  for (const auto& [name, value] : headers) {
    if (name == lower_case_name) return &value;
  }
  return nullptr;
}

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(const HttpServerConfig& config) {
  if (absl::Status valid = ValidateHttpServerConfig(config); !valid.ok()) return valid;
  if (config.port < 0) return absl::InvalidArgumentError("--http_port: -1 means no HTTP port");
  std::unique_ptr<HttpServer> server(new HttpServer(config));
  const std::string ports = absl::StrCat(config.address, ":", config.port);
  const std::string threads = absl::StrCat(config.threads);
  const std::string timeout = absl::StrCat(config.request_timeout_ms);
  const std::string keep_alive = absl::StrCat(config.keep_alive_ms);
  // No document_root: civetweb opens no file. access_control_allow_origin empty: civetweb
  // answers no CORS preflight itself (its default is "*"); AddCommonHeaders does, if asked.
  const char* options[] = {"listening_ports",
                           ports.c_str(),
                           "num_threads",
                           threads.c_str(),
                           "request_timeout_ms",
                           timeout.c_str(),
                           "enable_keep_alive",
                           config.keep_alive_ms > 0 ? "yes" : "no",
                           "keep_alive_timeout_ms",
                           keep_alive.c_str(),
                           // The header and the body go out in two writes: without it Nagle
                           // holds the body for the client's delayed ACK (40 ms a call).
                           "tcp_nodelay",
                           "1",
                           "access_control_allow_origin",
                           "",
                           "access_control_allow_methods",
                           "",
                           "access_control_allow_headers",
                           "",
                           nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = QuietLog;
  server->context_ = mg_start(&callbacks, nullptr, options);
  if (server->context_ == nullptr) {
    return absl::UnavailableError(absl::StrCat(
        "--http_address/--http_port: could not listen on ", ports,
        " (in use, an unknown host, or not an address of this machine)"));
  }
  mg_server_port bound[4] = {};
  const int count = mg_get_server_ports(server->context_, 4, bound);
  server->port_ = count > 0 ? bound[0].port : 0;
  // Every path comes to OnRequest ("/" matches as a prefix), which serves only the routes.
  mg_set_request_handler(server->context_, "/", &HttpServer::OnRequest, server.get());
  return server;
}

namespace {

// civetweb's listener polls its sockets in 2 s quanta before it looks at the stop flag, so
// mg_stop alone takes up to 2 s. A connection to the port wakes it at once: while mg_stop runs,
// connect every 20 ms (at most 150 times) until it returns. Only for an IPv4 listener (the
// wildcard reached through loopback); any other stops in its own time.
void StopWakingTheListener(mg_context* context, const std::string& address, int port) {
  std::atomic<bool> stopped{false};
  std::thread stopper([&] {
    mg_stop(context);
    stopped = true;
  });
  sockaddr_in target{};
  target.sin_family = AF_INET;
  target.sin_port = htons(static_cast<uint16_t>(port));
  const bool ipv4 =
      inet_pton(AF_INET, address == "0.0.0.0" ? "127.0.0.1" : address.c_str(), &target.sin_addr) == 1;
  for (int i = 0; ipv4 && i < 150 && !stopped; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) break;
    connect(fd, reinterpret_cast<const sockaddr*>(&target), sizeof(target));
    close(fd);
  }
  stopper.join();
}

}  // namespace

HttpServer::~HttpServer() {
  if (context_ != nullptr) StopWakingTheListener(context_, config_.address, port_);
}

void HttpServer::Handle(std::string method, std::string path, HttpHandler handler) {
  AddRoute({std::move(method), std::move(path), false, std::move(handler)});
}

void HttpServer::HandlePrefix(std::string method, std::string prefix, HttpHandler handler) {
  AddRoute({std::move(method), std::move(prefix), true, std::move(handler)});
}

void HttpServer::AddRoute(Route route) {
  std::unique_lock lock(routes_mutex_);
  for (Route& existing : routes_) {
    if (existing.method == route.method && existing.path == route.path &&
        existing.prefix == route.prefix) {
      existing = std::move(route);
      return;
    }
  }
  routes_.push_back(std::move(route));
}

void HttpServer::AddCommonHeaders(const HttpRequest& request, HttpResponse& response) const {
  std::vector<std::pair<std::string, std::string>> headers;
  bool has_csp = false;
  for (const auto& header : response.headers) {
    has_csp = has_csp || absl::EqualsIgnoreCase(header.first, "Content-Security-Policy");
  }
  // A handler's own policy governs framing through its frame-ancestors (browsers ignore
  // X-Frame-Options beside it), so DENY goes only with the default policy: the page's report
  // frame is framed by the page itself.
  if (!has_csp) {
    headers.emplace_back("Content-Security-Policy", kDefaultContentSecurityPolicy);
    headers.emplace_back("X-Frame-Options", "DENY");
  }
  for (const auto& [name, value] : kSecurityHeaders) headers.emplace_back(name, value);
  const std::string* origin = request.Header("origin");
  if (!config_.cors_origin.empty() && origin != nullptr &&
      (config_.cors_origin == "*" || *origin == config_.cors_origin)) {
    headers.emplace_back("Access-Control-Allow-Origin",
                         config_.cors_origin == "*" ? "*" : config_.cors_origin);
    headers.emplace_back("Access-Control-Expose-Headers", "X-Request-Id");
    headers.emplace_back("Vary", "Origin");
  }
  for (auto& header : response.headers) headers.push_back(std::move(header));
  response.headers = std::move(headers);
}

HttpResponse HttpServer::Route404or405(const HttpRequest& request) const {
  // Called with routes_mutex_ held shared. The methods the path has, for 405's Allow.
  std::vector<std::string> allowed;
  for (const Route& route : routes_) {
    const bool matches = route.prefix ? absl::StartsWith(request.path, route.path)
                                      : request.path == route.path;
    if (matches && std::find(allowed.begin(), allowed.end(), route.method) == allowed.end()) {
      allowed.push_back(route.method);
    }
  }
  if (allowed.empty()) {
    return JsonError(404, "not_found", absl::StrCat("no such path: ", request.path));
  }
  std::sort(allowed.begin(), allowed.end());
  const std::string allow = absl::StrJoin(allowed, ", ");
  // A CORS preflight (OPTIONS with Access-Control-Request-Method) of a route, when an origin
  // is configured: allowed, with the methods and headers the route takes.
  if (request.method == "OPTIONS" && !config_.cors_origin.empty() &&
      request.Header("access-control-request-method") != nullptr) {
    HttpResponse response;
    response.status = 204;
    response.SetHeader("Access-Control-Allow-Methods", allow);
    response.SetHeader("Access-Control-Allow-Headers", kCorsAllowHeaders);
    response.SetHeader("Access-Control-Max-Age", "600");
    return response;
  }
  HttpResponse response = JsonError(
      405, "unimplemented", absl::StrCat(request.method, " is not allowed on ", request.path, " (allowed: ", allow,
                        ")"));
  response.SetHeader("Allow", allow);
  return response;
}

HttpResponse HttpServer::Respond(const HttpRequest& request) const {
  HttpResponse response;
  {
    std::shared_lock lock(routes_mutex_);
    const Route* best = nullptr;
    for (const Route& route : routes_) {
      if (route.method != request.method) continue;
      if (!route.prefix && route.path == request.path) {
        best = &route;
        break;
      }
      if (route.prefix && absl::StartsWith(request.path, route.path) &&
          (best == nullptr || route.path.size() > best->path.size())) {
        best = &route;
      }
    }
    if (best == nullptr) {
      response = Route404or405(request);
    } else {
      const HttpHandler handler = best->handler;  // a copy: the lock is not held while it runs
      lock.unlock();
      response = handler(request);
    }
  }
  AddCommonHeaders(request, response);
  return response;
}

int HttpServer::OnRequest(mg_connection* connection, void* self_pointer) {
  const HttpServer& self = *static_cast<const HttpServer*>(self_pointer);
  const Clock::time_point start = Clock::now();
  const mg_request_info* info = mg_get_request_info(connection);
  HttpRequest request;
  request.method = info->request_method != nullptr ? info->request_method : "";
  request.path = info->local_uri != nullptr ? info->local_uri : "";
  request.query = info->query_string != nullptr ? info->query_string : "";
  request.remote_address = info->remote_addr;
  for (int i = 0; i < info->num_headers; ++i) {
    request.headers.emplace_back(absl::AsciiStrToLower(info->http_headers[i].name),
                                 info->http_headers[i].value);
  }
  const int64_t limit = self.config_.max_body_bytes;
  bool continued = false;  // an interim 100 Continue was sent (below)
  const auto fail = [&](HttpResponse response) {
    // The rest of the body is not read, so the connection cannot carry another request.
    response.SetHeader("Connection", "close");
    self.AddCommonHeaders(request, response);
    Send(connection, response, continued);
    return response.status;
  };
  if (info->content_length > limit) {
    return fail(JsonError(
        413, "resource_exhausted", absl::StrCat("request body: ", info->content_length,
                          " bytes (Content-Length) is over the server limit "
                          "--http_max_body_bytes=",
                          limit)));
  }
  // A client that asked to be told before it sends the body (curl does above 1 MiB) is told
  // now that it fits; civetweb does not answer Expect itself, and the client would otherwise
  // wait a second (curl) or for ever before sending.
  if (const std::string* expect = request.Header("expect");
      expect != nullptr && absl::EqualsIgnoreCase(*expect, "100-continue")) {
    static constexpr char kContinue[] = "HTTP/1.1 100 Continue\r\n\r\n";
    mg_write(connection, kContinue, sizeof(kContinue) - 1);
    continued = true;
  }
  // Read the body: chunked bodies (no Content-Length) are cut at the limit too, and the whole
  // read is bounded in time besides civetweb's per-read timeout.
  const auto time_limit = std::chrono::milliseconds(self.config_.request_timeout_ms);
  if (info->content_length > 0) request.body.reserve(static_cast<size_t>(info->content_length));
  // On the heap: civetweb's threads have 100 KiB stacks (below), and civetweb's own printf
  // puts 8 KiB more on them when the answer is sent (ASan's redzones overflowed 64 KiB here).
  std::vector<char> buffer(64 * 1024);
  while (true) {
    const int n = mg_read(connection, buffer.data(), buffer.size());
    if (n == 0) break;
    if (n < 0 || Clock::now() - start > time_limit) {
      return fail(JsonError(408, "deadline_exceeded", absl::StrCat("request body: not received within "
                                               "--http_request_timeout_ms=",
                                               self.config_.request_timeout_ms)));
    }
    if (static_cast<int64_t>(request.body.size()) + n > limit) {
      return fail(JsonError(413, "resource_exhausted", absl::StrCat("request body: over the server limit "
                                               "--http_max_body_bytes=",
                                               limit, " bytes")));
    }
    request.body.append(buffer.data(), static_cast<size_t>(n));
  }
  // The handler runs on a thread of its own: Debian builds civetweb with 100 KiB thread stacks
  // (USE_STACK_SIZE=102400), too small for protobuf's JSON parser, a gRPC call (whose inline
  // handler may run on the calling thread) or the readers' nesting; a std::thread gets the
  // process default (8 MiB). --http_threads still bounds how many run: this one waits for it.
  HttpResponse response;
  std::thread handler([&] { response = self.Respond(request); });
  handler.join();
  Send(connection, response, continued);
  return response.status;
}

}  // namespace koma::server

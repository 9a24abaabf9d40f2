#include "client/websocket_client.h"

#include <civetweb.h>

#include <mutex>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace koma::client {
namespace {

// RFC 6455 section 5.2: the first byte of a frame, FIN then the opcode in the low 4 bits.
constexpr int kFinBit = 0x80;
constexpr int kOpcodeMask = 0x0f;

void InitCivetwebOnce() {
  static std::once_flag once;
  std::call_once(once, [] { mg_init_library(0); });  // 0: no TLS (ws:// only)
}

}  // namespace

absl::StatusOr<WebSocketUrl> ParseWebSocketUrl(const std::string& url) {
  std::string rest = url;
  if (absl::StartsWithIgnoreCase(rest, "wss://")) {
    return absl::InvalidArgumentError(
        absl::StrCat("\"", url, "\": wss:// (TLS) is not supported; use ws://"));
  }
  const bool has_scheme = absl::StartsWithIgnoreCase(rest, "ws://");
  if (has_scheme) rest = rest.substr(5);
  WebSocketUrl parsed;
  const size_t slash = rest.find('/');
  if (slash != std::string::npos) {
    parsed.path = rest.substr(slash);
    rest = rest.substr(0, slash);
  }
  std::string port;
  bool port_given = false;  // a ':' after the host, even with nothing after it
  if (!rest.empty() && rest.front() == '[') {  // [IPv6]
    const size_t close = rest.find(']');
    if (close == std::string::npos) {
      return absl::InvalidArgumentError(absl::StrCat("\"", url, "\": unclosed [ in the host"));
    }
    parsed.host = rest.substr(1, close - 1);
    if (close + 1 < rest.size()) {
      if (rest[close + 1] != ':') {
        return absl::InvalidArgumentError(absl::StrCat("\"", url, "\": bad host"));
      }
      port = rest.substr(close + 2);
      port_given = true;
    }
  } else {
    const size_t colon = rest.find(':');
    parsed.host = rest.substr(0, colon);
    if (colon != std::string::npos) {
      port = rest.substr(colon + 1);
      port_given = true;
    }
  }
  if (parsed.host.empty()) {
    return absl::InvalidArgumentError(
        absl::StrCat("\"", url, "\" has no host (ws://localhost:8001)"));
  }
  if (port.empty() && (!has_scheme || port_given)) {
    return absl::InvalidArgumentError(
        absl::StrCat("\"", url, "\" must be ws://HOST:PORT or HOST:PORT (ws://localhost:8001)"));
  }
  if (!port.empty() &&
      (!absl::SimpleAtoi(port, &parsed.port) || parsed.port < 1 || parsed.port > 65535 ||
       port.find_first_not_of("0123456789") != std::string::npos)) {
    return absl::InvalidArgumentError(
        absl::StrCat("\"", url, "\": port \"", port, "\" must be a number in [1, 65535]"));
  }
  return parsed;
}

absl::StatusOr<std::unique_ptr<WebSocketClient>> WebSocketClient::Connect(
    const WebSocketUrl& url) {
  InitCivetwebOnce();
  std::unique_ptr<WebSocketClient> client(new WebSocketClient());
  char error[256] = "";
  const std::string host = url.host;
  client->connection_ = mg_connect_websocket_client(
      host.c_str(), url.port, /*use_ssl=*/0, error, sizeof(error), url.path.c_str(),
      /*origin=*/nullptr, &WebSocketClient::OnData, &WebSocketClient::OnClose, client.get());
  if (client->connection_ == nullptr) {
    return absl::UnavailableError(absl::StrCat("cannot open ws://", url.host, ":", url.port,
                                               url.path, ": ", error[0] ? error : "refused"));
  }
  return client;
}

WebSocketClient::~WebSocketClient() { Close(); }

int WebSocketClient::OnData(mg_connection* connection, int flags, char* data, size_t size,
                            void* self) {
  (void)connection;
  auto* client = static_cast<WebSocketClient*>(self);
  const int opcode = flags & kOpcodeMask;
  std::lock_guard<std::mutex> lock(client->mutex_);
  switch (opcode) {
    case MG_WEBSOCKET_OPCODE_TEXT:
    case MG_WEBSOCKET_OPCODE_BINARY:
      client->partial_.assign(data, size);
      break;
    case MG_WEBSOCKET_OPCODE_CONTINUATION:
      client->partial_.append(data, size);
      break;
    case MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE:
      client->closed_ = true;
      client->arrived_.notify_all();
      return 0;  // civetweb closes the connection
    default:       // ping (civetweb answers it), pong
      return 1;
  }
  if (flags & kFinBit) {
    client->messages_.push_back(std::move(client->partial_));
    client->partial_.clear();
    client->arrived_.notify_all();
  }
  return 1;
}

void WebSocketClient::OnClose(const mg_connection* connection, void* self) {
  (void)connection;
  auto* client = static_cast<WebSocketClient*>(self);
  std::lock_guard<std::mutex> lock(client->mutex_);
  client->closed_ = true;
  client->arrived_.notify_all();
}

absl::Status WebSocketClient::SendText(const std::string& text) {
  if (closed()) return absl::UnavailableError("the connection is closed");
  std::lock_guard<std::mutex> lock(send_mutex_);
  if (connection_ == nullptr) return absl::UnavailableError("the connection is closed");
  const int sent = mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_TEXT, text.data(),
                                             text.size());
  if (sent <= 0) {
    std::lock_guard<std::mutex> state(mutex_);
    closed_ = true;
    return absl::UnavailableError("the connection closed while sending");
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> WebSocketClient::Receive(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait_for(lock, timeout, [this] { return !messages_.empty() || closed_; });
  if (!messages_.empty()) {
    std::string message = std::move(messages_.front());
    messages_.pop_front();
    return message;
  }
  if (closed_) return absl::UnavailableError("the connection closed");
  return absl::DeadlineExceededError("no message");
}

bool WebSocketClient::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

void WebSocketClient::Close() {
  std::lock_guard<std::mutex> lock(send_mutex_);
  if (connection_ == nullptr) return;
  if (!closed()) {
    const char normal_closure[2] = {0x03, static_cast<char>(0xe8)};  // status 1000, big-endian
    mg_websocket_client_write(connection_, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, normal_closure,
                              sizeof(normal_closure));
  }
  mg_close_connection(connection_);  // joins civetweb's reader thread
  connection_ = nullptr;
  std::lock_guard<std::mutex> state(mutex_);
  closed_ = true;
}

}  // namespace koma::client

// A WebSocket (RFC 6455) text client through Debian's civetweb (mg_connect_websocket_client):
// what `koma live --vts` talks to VTube Studio with. civetweb reads on a thread of its own and
// calls back with each frame; whole text messages queue here until Receive takes them. Send
// and Receive may be called from different threads.
#ifndef KOMA_CLIENT_WEBSOCKET_CLIENT_H_
#define KOMA_CLIENT_WEBSOCKET_CLIENT_H_

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

struct mg_connection;

namespace koma::client {

// A ws:// URL's parts. "ws://HOST[:PORT][/PATH]" (port 80 when absent, path "/"), or
// "HOST:PORT". wss:// (TLS) is refused: VTube Studio serves plain ws:// on the local network.
struct WebSocketUrl {
  std::string host;
  int port = 80;
  std::string path = "/";
};
absl::StatusOr<WebSocketUrl> ParseWebSocketUrl(const std::string& url);

class WebSocketClient {
 public:
  // Connects and completes the opening handshake. UNAVAILABLE naming the URL and civetweb's
  // reason when nothing listens there or the handshake fails.
  static absl::StatusOr<std::unique_ptr<WebSocketClient>> Connect(const WebSocketUrl& url);
  ~WebSocketClient();  // Close()
  WebSocketClient(const WebSocketClient&) = delete;
  WebSocketClient& operator=(const WebSocketClient&) = delete;

  // One text message. UNAVAILABLE once the connection is closed.
  absl::Status SendText(const std::string& text);
  // The next whole text (or binary) message, waiting at most `timeout`: DEADLINE_EXCEEDED when
  // none came, UNAVAILABLE when the connection closed and nothing is left queued.
  absl::StatusOr<std::string> Receive(std::chrono::milliseconds timeout);
  bool closed() const;
  // Sends a close frame (1000, normal) and stops civetweb's reader thread. Idempotent.
  void Close();

 private:
  WebSocketClient() = default;
  static int OnData(mg_connection* connection, int flags, char* data, size_t size, void* self);
  static void OnClose(const mg_connection* connection, void* self);

  mg_connection* connection_ = nullptr;
  std::mutex send_mutex_;  // one writer at a time (the frame thread and a keep-alive thread)
  mutable std::mutex mutex_;  // guards the fields below
  std::condition_variable arrived_;
  std::deque<std::string> messages_;
  std::string partial_;  // a fragmented message's frames so far
  bool closed_ = false;
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_WEBSOCKET_CLIENT_H_

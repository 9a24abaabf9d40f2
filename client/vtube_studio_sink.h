// `koma live --vts [URL]`: each grid frame into VTube Studio through its public API
// (client/vts_messages.h; default ws://localhost:8001). Start connects and authenticates:
// with the token saved by an earlier run (--vts-token-file) an AuthenticationRequest is
// enough; without one, or when VTube Studio refuses it, an AuthenticationTokenRequest makes
// VTube Studio ask the user to allow "koma", and the token it answers is saved. Then every
// frame is one InjectParameterDataRequest (faceFound false, mode "set") of MouthOpen,
// EyeOpenLeft and EyeOpenRight (0..1; --vts-mouth-param and the eye flags rename them).
// VTube Studio forgets an injected value after about 1 s without one, so the last values are
// sent again every 0.5 s while no frame comes (a stalled network, a paused stream).
#ifndef KOMA_CLIENT_VTUBE_STUDIO_SINK_H_
#define KOMA_CLIENT_VTUBE_STUDIO_SINK_H_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/avatar_levels.h"
#include "client/live_sink.h"
#include "client/vts_messages.h"
#include "client/websocket_client.h"

namespace koma::client {

inline constexpr char kVtsDefaultUrl[] = "ws://localhost:8001";

struct VtsOptions {
  std::string url = kVtsDefaultUrl;
  std::string token_file;  // "" = DefaultVtsTokenFile()
  VtsPlugin plugin;
  // VTube Studio's input parameters (its defaults; the model maps them to Live2D parameters).
  std::string mouth_parameter = "MouthOpen";
  std::string eye_left_parameter = "EyeOpenLeft";
  std::string eye_right_parameter = "EyeOpenRight";
  std::chrono::milliseconds allow_timeout{120000};  // for the user to click Allow
  std::chrono::milliseconds reply_timeout{10000};   // for any other answer
  std::chrono::milliseconds resend_after{500};      // idle time before the values are re-sent
};

// $XDG_CONFIG_HOME/koma/vts-token, else $HOME/.config/koma/vts-token; "" when neither is set.
std::string DefaultVtsTokenFile();
// The saved token (surrounding white space removed). NOT_FOUND when the file does not exist.
absl::StatusOr<std::string> ReadVtsToken(const std::string& path);
// Saves the token readable by its owner only (0600), creating the folders, replacing the file
// atomically (a rename).
absl::Status WriteVtsToken(const std::string& path, const std::string& token);

// The values of one frame, in the order sent: mouth, left eye, right eye (one blink timing).
std::vector<VtsParameterValue> VtsValuesOf(const v1::LiveLipBlinkFrame& frame,
                                           const AvatarLevels& levels, const VtsOptions& options);

class VtubeStudioSink : public LiveSink {
 public:
  explicit VtubeStudioSink(VtsOptions options);
  ~VtubeStudioSink() override;

  // Connects and authenticates (above); errors name VTube Studio's errorID and message, and
  // say what the user can do (turn the plugin API on, click Allow).
  absl::Status Start(const v1::LiveLipBlinkSetup& setup) override;
  // Sends the frame's values without waiting for the answer. An APIError answer is printed
  // once per errorID; VTube Studio closing the connection or revoking access (errorID 8, 50)
  // ends the stream.
  absl::Status Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) override;
  // Stops the re-sending, reads the last answers, closes the connection.
  absl::Status Close() override;

  int64_t injects_sent() const;

 private:
  absl::StatusOr<VtsResponse> Call(const std::string& request, const std::string& request_id,
                                   std::chrono::milliseconds timeout);
  absl::Status Authenticate();
  absl::StatusOr<bool> AuthenticateWithToken(const std::string& token);
  // Sends `values_` as request `id` (mutex_ held).
  absl::Status SendValuesLocked(const std::string& id);
  // Reads the answers received so far (mutex_ held).
  void ReadAnswersLocked();
  void ResendLoop();

  VtsOptions options_;
  AvatarLevels levels_;
  std::unique_ptr<WebSocketClient> socket_;
  std::thread resender_;

  mutable std::mutex mutex_;  // guards the fields below (the frame thread and resender_)
  std::condition_variable wake_;
  bool stop_ = false;
  std::vector<VtsParameterValue> values_;  // the last frame's; empty before the first
  std::chrono::steady_clock::time_point last_sent_;
  int64_t injects_sent_ = 0;
  int64_t resends_ = 0;  // of injects_sent_, the values re-sent while no frame came
  std::map<int, int64_t> errors_seen_;  // errorID -> count of APIError answers
  absl::Status failure_;                // set when the stream must end
  bool failure_returned_ = false;       // Frame has returned failure_
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_VTUBE_STUDIO_SINK_H_

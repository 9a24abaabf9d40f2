// `koma live --vmc [HOST:PORT]`: each grid frame as one OSC bundle over UDP in the VMC
// protocol (Virtual Motion Capture; VSeeFace, VMagicMirror, Warudo and VNyan receive it):
//   /VMC/Ext/Blend/Val ,sf  <mouth clip> <0..1>     the mouth drawing (closed 0, mid, open 1)
//   /VMC/Ext/Blend/Val ,sf  <blink clip> <0..1>     1 - how open the eyes are (1: shut)
//   /VMC/Ext/Blend/Apply                            apply both at once
// The clips are VRM 0.x presets by default ("A", "Blink"; VRM 1.0 names them "aa", "blink").
// Sent through Debian's liblo. UDP has no answer: a receiver that is not running loses the
// frames, with one warning on stderr, and the stream goes on (docs/live.md).
#ifndef KOMA_CLIENT_VMC_SINK_H_
#define KOMA_CLIENT_VMC_SINK_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/avatar_levels.h"
#include "client/live_sink.h"

namespace koma::client {

inline constexpr char kVmcDefaultTarget[] = "127.0.0.1:39539";  // VSeeFace's receiver port

struct VmcOptions {
  std::string host = "127.0.0.1";
  std::string port = "39539";
  std::string mouth_clip = "A";      // VRM 0.x preset "A" (VRM 1.0: "aa")
  std::string blink_clip = "Blink";  // VRM 0.x preset "Blink" (VRM 1.0: "blink")
};

// "HOST:PORT" ("[::1]:PORT" for an IPv6 address) into options' host and port. Empty: the
// default 127.0.0.1:39539. INVALID_ARGUMENT naming `flag` for a missing host, or a port that
// is not 1..65535.
absl::Status ParseVmcTarget(const std::string& target, const char* flag, VmcOptions& options);

// One blend shape clip's value.
struct VmcBlend {
  std::string clip;
  float value = 0.0f;  // 0..1
};

// The values of one frame, in the order they are sent: the mouth clip, then the blink clip.
std::vector<VmcBlend> VmcBlendsOf(const v1::LiveLipBlinkFrame& frame, const AvatarLevels& levels,
                                  const VmcOptions& options);

// The bundle's bytes as sent (OSC 1.0: "#bundle", the immediate time tag, each message with its
// size): what the unit tests decode.
std::string VmcBundleBytes(const std::vector<VmcBlend>& blends);

class VmcSink : public LiveSink {
 public:
  // The liblo address of options' host and port (resolved when first sent to).
  static absl::StatusOr<std::unique_ptr<VmcSink>> Open(const VmcOptions& options);
  ~VmcSink() override;

  absl::Status Start(const v1::LiveLipBlinkSetup& setup) override;
  absl::Status Frame(const v1::LiveLipBlinkFrame& frame, const LiveFrameTiming& timing) override;
  absl::Status Close() override;

  int64_t bundles_sent() const { return bundles_sent_; }

 private:
  VmcSink(const VmcOptions& options, void* address);

  VmcOptions options_;
  void* address_;  // lo_address (kept out of this header: liblo's headers stay in vmc_sink.cc)
  AvatarLevels levels_;
  int64_t bundles_sent_ = 0;
  int64_t bundles_lost_ = 0;
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_VMC_SINK_H_

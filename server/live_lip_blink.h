// LiveLipBlink's messages (docs/api.md, "LiveLipBlink"): the setup checked and turned into the
// core's LiveVoiceOptions (core/live_voice.h), audio messages decoded to mono samples, decided
// frames as response messages. The stream itself is server/live_stream.h.
#ifndef KOMA_SERVER_LIVE_LIP_BLINK_H_
#define KOMA_SERVER_LIVE_LIP_BLINK_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/live_voice.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// The setup's sample rates, Hz: telephone audio to the fastest capture cards.
inline constexpr int kMinLiveSampleRate = 1000;
inline constexpr int kMaxLiveSampleRate = 384000;
// A setup's lookahead when unset, grid frames.
inline constexpr int kDefaultLiveLookahead = 2;

// INVALID_ARGUMENT naming the field ("setup.channels: 9 exceeds the server limit
// --max_audio_channels=8"); the fields that are for curves (mouth.ids, eyes.threshold, ...)
// must be unset.
absl::StatusOr<LiveVoiceOptions> LiveOptionsFromSetup(const v1::LiveLipBlinkSetup& setup,
                                                      const RequestLimits& limits);

// An audio message's interleaved samples mixed to mono (the mean of the channels, full scale
// +-1, as the offline decoder), appended to `mono`. INVALID_ARGUMENT when the bytes are not
// whole sample frames, naming the message's index and the frame size, or when a mixed sample is
// not finite (F32 NaN or infinity), naming the message and the sample frame.
class LiveAudioDecoder {
 public:
  LiveAudioDecoder(v1::LiveSampleFormat format, int channels)
      : format_(format), channels_(channels) {}
  int bytes_per_frame() const;
  absl::Status Decode(const std::string& bytes, int64_t message_index,
                      std::vector<float>* mono) const;

 private:
  v1::LiveSampleFormat format_;
  int channels_;
};

// A decided frame as its message; late_ms from the frame's late samples at `sample_rate`.
void LiveFrameToProto(const LiveFrame& frame, int sample_rate, v1::LiveLipBlinkFrame* out);

}  // namespace koma::server

#endif  // KOMA_SERVER_LIVE_LIP_BLINK_H_

// LipBlink from a voice (LipBlinkRequest.audio or .rhubarb_cues; docs/semantics.md, "LipBlink
// from a voice"): the recording decoded block by block (formats/audio_reader.h) into each
// analysis frame's loudness, speech found there (core/voice_activity.h), or Rhubarb's cues
// sampled there (core/mouth_cues.h); then the ordinary LipBlink job on the request's motion,
// or on a new one covering the recording, with the mouth curves' speech and drawings taken
// from the voice. The response adds the analysis, the mouth cues, and the file.
#ifndef KOMA_SERVER_LIP_BLINK_VOICE_H_
#define KOMA_SERVER_LIP_BLINK_VOICE_H_

#include "absl/status/status.h"
#include "core/voice_activity.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// The motion rate of a voice-only request whose voice_motion_fps is unset.
inline constexpr double kDefaultVoiceMotionFps = 30.0;

// LipBlinkVoiceSettings as core options (unchecked: ValidateVoiceOptions).
VoiceOptions VoiceOptionsFromProto(const v1::LipBlinkVoiceSettings& in);

struct LipBlinkMotionShape;  // server/lip_blink_request.h

absl::Status HandleLipBlinkVoice(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                 v1::LipBlinkResponse* response, LipBlinkMotionShape* shape);

}  // namespace koma::server

#endif  // KOMA_SERVER_LIP_BLINK_VOICE_H_

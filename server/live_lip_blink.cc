#include "server/live_lip_blink.h"

#include <cmath>
#include <cstring>
#include <utility>

#include "absl/strings/str_cat.h"
#include "convert/field_error.h"
#include "core/status_macros.h"
#include "server/lip_blink_request.h"
#include "server/lip_blink_voice.h"

namespace koma::server {
namespace {

using convert::Prefixed;

absl::Status Unsupported(absl::string_view field, absl::string_view why) {
  return absl::InvalidArgumentError(absl::StrCat("setup.", field, ": must be unset (", why, ")"));
}

// The setup's mouth and eye fields that only mean something for curves.
absl::Status CheckCurveFieldsUnset(const v1::LiveLipBlinkSetup& setup) {
  if (!setup.mouth().ids().empty()) return Unsupported("mouth.ids", "a live stream has no curves");
  if (!setup.mouth().speech().empty()) {
    return Unsupported("mouth.speech", "the voice gives the speech");
  }
  if (!setup.eyes().ids().empty()) return Unsupported("eyes.ids", "a live stream has no curves");
  if (setup.eyes().has_threshold()) {
    return Unsupported("eyes.threshold", "it finds blinks in eye curves; a live stream has none");
  }
  if (setup.eyes().has_linked()) {
    return Unsupported("eyes.linked", "it links eye curves; a live stream has one pair of eyes");
  }
  if (!setup.eyes().auto_blink().keep().empty()) {
    return Unsupported("eyes.auto_blink.keep", "frames to keep are not known ahead of a stream");
  }
  return absl::OkStatus();
}

float S16(const char* p) {
  int16_t v;
  std::memcpy(&v, p, sizeof v);  // little-endian hosts only (x86-64, arm64)
  return static_cast<float>(v) * (1.0f / 32768.0f);
}
float F32(const char* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

absl::StatusOr<LiveVoiceOptions> LiveOptionsFromSetup(const v1::LiveLipBlinkSetup& setup,
                                                      const RequestLimits& limits) {
  if (setup.sample_rate() < kMinLiveSampleRate || setup.sample_rate() > kMaxLiveSampleRate) {
    return absl::InvalidArgumentError(absl::StrCat("setup.sample_rate: ", setup.sample_rate(),
                                                   " must be in [", kMinLiveSampleRate, ", ",
                                                   kMaxLiveSampleRate, "] samples per second"));
  }
  if (setup.channels() < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat("setup.channels: ", setup.channels(), " must be at least 1"));
  }
  if (setup.channels() > limits.max_audio_channels) {
    return absl::InvalidArgumentError(
        absl::StrCat("setup.channels: ", setup.channels(),
                     " exceeds the server limit --max_audio_channels=", limits.max_audio_channels));
  }
  if (setup.sample_format() != v1::LIVE_SAMPLE_S16LE &&
      setup.sample_format() != v1::LIVE_SAMPLE_F32LE) {
    return absl::InvalidArgumentError(absl::StrCat(
        "setup.sample_format: ", static_cast<int>(setup.sample_format()),
        " is not a sample format (1 LIVE_SAMPLE_S16LE, 2 LIVE_SAMPLE_F32LE)"));
  }
  KOMA_RETURN_IF_ERROR(CheckCurveFieldsUnset(setup));
  LiveVoiceOptions o;
  o.sample_rate = setup.sample_rate();
  o.frame_fps = setup.has_timing_fps() ? setup.timing_fps() : kDefaultTimingFps;
  if (!(o.frame_fps > 0.0 && o.frame_fps <= kMaxTimingFps)) {
    return absl::InvalidArgumentError(absl::StrCat("setup.timing_fps: ", o.frame_fps,
                                                   " must be in (0, 1000] frames per second"));
  }
  o.lookahead_frames =
      setup.has_lookahead_frames() ? setup.lookahead_frames() : kDefaultLiveLookahead;
  if (o.lookahead_frames < 0 || o.lookahead_frames > kMaxLookaheadFrames) {
    return absl::InvalidArgumentError(absl::StrCat("setup.lookahead_frames: ",
                                                   o.lookahead_frames, " must be in [0, ",
                                                   kMaxLookaheadFrames, "] grid frames"));
  }
  o.voice = VoiceOptionsFromProto(setup.voice_settings());
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateVoiceOptions(o.voice), "setup.voice_settings."));
  absl::StatusOr<MouthOptions> mouth = MouthOptionsFromProto(setup.mouth(), 0);
  if (!mouth.ok()) return Prefixed(mouth.status(), "setup.");
  o.mouth = *std::move(mouth);
  absl::StatusOr<EyeOptions> eyes = EyeOptionsFromProto(setup.eyes(), o.frame_fps, 0);
  if (!eyes.ok()) return Prefixed(eyes.status(), "setup.");
  o.eyes = *std::move(eyes);
  o.seed = setup.has_seed() ? setup.seed() : kDefaultLipBlinkSeed;
  KOMA_RETURN_IF_ERROR(Prefixed(ValidateLiveVoiceOptions(o), "setup."));
  return o;
}

int LiveAudioDecoder::bytes_per_frame() const {
  return channels_ * (format_ == v1::LIVE_SAMPLE_S16LE ? 2 : 4);
}

absl::Status LiveAudioDecoder::Decode(const std::string& bytes, int64_t message_index,
                                      std::vector<float>* mono) const {
  const size_t frame_bytes = static_cast<size_t>(bytes_per_frame());
  if (bytes.size() % frame_bytes != 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "audio (message ", message_index, "): ", bytes.size(),
        " bytes is not a whole number of sample frames (", channels_, " channel",
        channels_ == 1 ? "" : "s", " x ", frame_bytes / channels_, " bytes = ", frame_bytes,
        " bytes each)"));
  }
  const size_t frames = bytes.size() / frame_bytes;
  const size_t sample_bytes = frame_bytes / channels_;
  float (*sample)(const char*) = format_ == v1::LIVE_SAMPLE_S16LE ? S16 : F32;
  const float scale = 1.0f / static_cast<float>(channels_);
  const size_t start = mono->size();
  mono->resize(start + frames);
  const char* p = bytes.data();
  for (size_t f = 0; f < frames; ++f) {
    float sum = 0.0f;
    for (int c = 0; c < channels_; ++c, p += sample_bytes) sum += sample(p);
    const float x = channels_ == 1 ? sum : sum * scale;
    if (!std::isfinite(x)) {  // F32 only: as the offline decoder, a NaN or infinity is refused
      mono->resize(start);
      return absl::InvalidArgumentError(absl::StrCat("audio (message ", message_index,
                                                     "): sample frame ", f,
                                                     " is not a finite number"));
    }
    (*mono)[start + f] = x;
  }
  return absl::OkStatus();
}

void LiveFrameToProto(const LiveFrame& frame, int sample_rate, v1::LiveLipBlinkFrame* out) {
  const auto shape = [](MouthShape s) {
    return s == MouthShape::kOpen ? v1::MOUTH_OPEN
           : s == MouthShape::kMid ? v1::MOUTH_MID
                                   : v1::MOUTH_CLOSED;
  };
  out->set_grid_frame(frame.frame);
  out->set_time_s(frame.time_s);
  out->set_speech(frame.speech);
  out->set_mouth(shape(frame.mouth));
  out->set_mouth_level(frame.mouth_level);
  out->set_new_drawing(frame.new_drawing);
  out->set_hold_start(frame.hold_start);
  out->set_eyes(shape(frame.eye));
  out->set_eye_level(frame.eye_level);
  out->set_blink_start(frame.blink_start);
  out->set_late_ms(1000.0 * static_cast<double>(frame.late_samples) / sample_rate);
  out->set_loudness_dbfs(frame.dbfs);
  out->set_noise_floor_dbfs(frame.noise_floor_dbfs);
}

}  // namespace koma::server

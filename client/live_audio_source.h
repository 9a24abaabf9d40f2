// Where `koma live` gets its audio (client/live_command.h): a recording played at real time
// (--input FILE, through formats/audio_reader.h) or a capture device through ALSA (--device
// NAME). Either hands out chunks of 10 ms of interleaved samples in the stream's format,
// LiveLipBlinkRequest.audio as is; the pacing to real time is the caller's (LivePacer).
#ifndef KOMA_CLIENT_LIVE_AUDIO_SOURCE_H_
#define KOMA_CLIENT_LIVE_AUDIO_SOURCE_H_

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

struct LiveAudioFormat {
  int sample_rate = 0;  // Hz
  int channels = 0;     // interleaved; the server mixes them to mono
  v1::LiveSampleFormat sample_format = v1::LIVE_SAMPLE_FORMAT_UNSPECIFIED;
  std::string description;  // for the summary: "voice.flac: FLAC / Signed 16 bit PCM"

  int bytes_per_frame() const {
    return channels * (sample_format == v1::LIVE_SAMPLE_F32LE ? 4 : 2);
  }
};

class LiveAudioSource {
 public:
  virtual ~LiveAudioSource() = default;
  virtual const LiveAudioFormat& format() const = 0;
  // The next chunk, whole sample frames (about 10 ms; a device's period), into `bytes`
  // (replaced); false at the end of a recording (a device has no end). Errors name the file
  // or the device.
  virtual absl::StatusOr<bool> Next(std::string* bytes) = 0;
  // True when the source keeps real time itself (a sound card: Next waits for the audio), so
  // the caller must not pace it: the card's clock and the computer's drift apart, and waiting
  // on the computer's would let the card's buffer overrun within minutes.
  virtual bool real_time() const { return false; }
};

// The recording at `path`, decoded by libsndfile (WAV, FLAC, Ogg Vorbis/Opus, MP3, ...), its
// own rate and channels: S16LE when its samples are 8- or 16-bit integers (exact), F32LE
// otherwise. Errors: "--input x.wav: cannot read ...: No such file or directory", "--input
// x.txt: not a recording libsndfile can read ...".
absl::StatusOr<std::unique_ptr<LiveAudioSource>> OpenLiveFile(const std::string& path);

// ALSA capture device `device` ("default", "hw:1,0", "null", ... as `arecord -L` lists them):
// 48 kHz mono S16LE, 10 ms periods (ALSA may give the nearest rate it has: format() says
// which). Errors name the device and ALSA's reason.
absl::StatusOr<std::unique_ptr<LiveAudioSource>> OpenLiveDevice(const std::string& device);

// Real time: the audio up to sample frame `end` is handed on no sooner than end / rate
// seconds (divided by `speed`) after the first chunk; `speed` 0 never waits. For a recording,
// and for ALSA's null device, which answers at once; a sound card keeps time itself
// (LiveAudioSource::real_time).
class LivePacer {
 public:
  LivePacer(int sample_rate, double speed);
  // Waits until the audio up to sample frame `end_frames` is due. Returns at once when
  // `stop` becomes true (polled every 10 ms).
  void WaitFor(int64_t end_frames, const std::atomic<bool>* stop = nullptr);

 private:
  int sample_rate_;
  double speed_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIVE_AUDIO_SOURCE_H_

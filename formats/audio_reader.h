// Recordings for LipBlink (docs/formats.md, "Audio"): decoded from memory with Debian's
// libsndfile through its virtual I/O (no temporary file), block by block, every block mixed to
// mono, so the caller's memory grows with what it keeps per block, not with the samples.
// Reads what libsndfile 1.2 reads: WAV (PCM 8/16/24/32-bit, float), FLAC, Ogg Vorbis and
// Opus, MP3, AIFF, CAF and the rest of its list.
#ifndef KOMA_FORMATS_AUDIO_READER_H_
#define KOMA_FORMATS_AUDIO_READER_H_

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/types/span.h"

namespace koma::formats {

inline constexpr int kMaxAudioSampleRate = 1'000'000;  // Hz (the film grid's limit)

struct AudioLimits {
  double max_seconds = 7200.0;  // longest recording decoded (the header's claim and the samples)
  int max_channels = 64;
  // Most samples decoded (sample frames x channels): the decoding work, which the rate, the
  // channels and the seconds only bound one by one. 10^9 is 2 h of 48 kHz stereo (0.69 G)
  // with room, a few seconds of decoding (docs/reliability.md).
  int64_t max_samples = 1'000'000'000;
};

struct AudioInfo {
  int sample_rate = 0;  // Hz
  int channels = 0;
  int64_t frames = 0;  // sample frames the header claims (libsndfile's count)
  // True when the samples are 8- or 16-bit PCM integers (WAV's, FLAC's, ...): decoded as
  // x / 32768, so a 16-bit integer holds each decoded sample exactly.
  bool pcm16 = false;
  std::string format;  // e.g. "WAV (Microsoft) / Signed 16 bit PCM"
};

class AudioDecoder {
 public:
  // Opens `bytes` (kept by reference: it must outlive the decoder). INVALID_ARGUMENT for an
  // empty or unreadable recording (libsndfile's reason), a sample rate outside
  // 1 .. kMaxAudioSampleRate, no channels; RESOURCE_EXHAUSTED for more channels than
  // limits.max_channels, or a header claiming more than limits.max_seconds or
  // limits.max_samples.
  static absl::StatusOr<std::unique_ptr<AudioDecoder>> Open(std::string_view bytes,
                                                            const AudioLimits& limits);
  ~AudioDecoder();
  AudioDecoder(const AudioDecoder&) = delete;
  AudioDecoder& operator=(const AudioDecoder&) = delete;

  const AudioInfo& info() const { return info_; }
  int64_t decoded() const { return decoded_; }  // sample frames handed out so far

  // The next block of mono samples (the channels' mean, full scale +-1); empty at the end.
  // INVALID_ARGUMENT for a decoding error or a sample that is not finite, RESOURCE_EXHAUSTED
  // past limits.max_seconds or limits.max_samples.
  absl::StatusOr<absl::Span<const float>> Next();

  // The next block of sample frames not mixed: info().channels floats per sample frame,
  // interleaved, full scale +-1; empty at the end. The same errors as Next, a sample that is
  // not finite named by its frame and channel. Use Next or NextInterleaved on one decoder.
  absl::StatusOr<absl::Span<const float>> NextInterleaved();

 private:
  // Decodes the next block into interleaved_: the sample frames read (0 at the end).
  absl::StatusOr<int64_t> ReadBlock();
  // The limits on decoded_ (after a block).
  absl::Status CheckDecodedLimits() const;

  struct Memory;
  AudioDecoder() = default;

  std::unique_ptr<Memory> memory_;
  void* file_ = nullptr;  // SNDFILE*
  AudioInfo info_;
  AudioLimits limits_;
  int64_t decoded_ = 0;
  std::vector<float> interleaved_;
  std::vector<float> mono_;
};

}  // namespace koma::formats

#endif  // KOMA_FORMATS_AUDIO_READER_H_

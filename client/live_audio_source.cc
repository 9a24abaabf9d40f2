#include "client/live_audio_source.h"

#include <alsa/asoundlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/types/span.h"
#include "client/files.h"
#include "formats/audio_reader.h"

namespace koma::client {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "LiveLipBlinkRequest.audio is little-endian: the samples are copied as they are");

constexpr int kChunksPerSecond = 100;  // 10 ms chunks

// A recording, decoded block by block, handed out in 10 ms chunks.
class FileSource : public LiveAudioSource {
 public:
  FileSource(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}

  absl::Status Open() {
    formats::AudioLimits limits;
    absl::StatusOr<std::unique_ptr<formats::AudioDecoder>> decoder =
        formats::AudioDecoder::Open(bytes_, limits);
    if (!decoder.ok()) return Named(decoder.status());
    decoder_ = *std::move(decoder);
    const formats::AudioInfo& info = decoder_->info();
    format_.sample_rate = info.sample_rate;
    format_.channels = info.channels;
    format_.sample_format = info.pcm16 ? v1::LIVE_SAMPLE_S16LE : v1::LIVE_SAMPLE_F32LE;
    format_.description = absl::StrCat(path_, ": ", info.format);
    return absl::OkStatus();
  }

  const LiveAudioFormat& format() const override { return format_; }

  absl::StatusOr<bool> Next(std::string* bytes) override {
    // Chunk k ends at sample frame floor((k + 1) x rate / 100): 10 ms, whatever the rate.
    const int64_t end = (chunks_ + 1) * static_cast<int64_t>(format_.sample_rate) / kChunksPerSecond;
    const size_t channels = static_cast<size_t>(format_.channels);
    size_t want = static_cast<size_t>(end - handed_) * channels;
    while (pending_.size() - used_ < want && !ended_) {
      absl::StatusOr<absl::Span<const float>> block = decoder_->NextInterleaved();
      if (!block.ok()) return Named(block.status());
      if (block->empty()) {
        ended_ = true;
        break;
      }
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(used_));
      used_ = 0;
      pending_.insert(pending_.end(), block->begin(), block->end());
    }
    want = std::min(want, pending_.size() - used_);
    if (want == 0) return false;
    const float* samples = pending_.data() + used_;
    if (format_.sample_format == v1::LIVE_SAMPLE_S16LE) {
      bytes->resize(want * 2);
      for (size_t i = 0; i < want; ++i) {
        // x / 32768 back to the integer it was decoded from.
        const float scaled = std::nearbyint(samples[i] * 32768.0f);
        const int16_t s = static_cast<int16_t>(std::clamp(scaled, -32768.0f, 32767.0f));
        std::memcpy(bytes->data() + 2 * i, &s, 2);
      }
    } else {
      bytes->resize(want * 4);
      std::memcpy(bytes->data(), samples, want * 4);
    }
    used_ += want;
    handed_ += static_cast<int64_t>(want / channels);
    ++chunks_;
    return true;
  }

 private:
  absl::Status Named(const absl::Status& status) const {
    return absl::Status(status.code(), absl::StrCat("--input ", path_, ": ", status.message()));
  }

  std::string path_;
  std::string bytes_;  // the file, which the decoder reads from
  std::unique_ptr<formats::AudioDecoder> decoder_;
  LiveAudioFormat format_;
  std::vector<float> pending_;  // decoded, interleaved, not yet handed out from used_
  size_t used_ = 0;
  int64_t handed_ = 0;  // sample frames handed out
  int64_t chunks_ = 0;
  bool ended_ = false;
};

// ALSA's own messages go to stderr by default; koma names the device in its own.
void QuietAlsa(const char*, int, const char*, int, const char*, ...) {}

class DeviceSource : public LiveAudioSource {
 public:
  explicit DeviceSource(std::string device) : device_(std::move(device)) {}
  ~DeviceSource() override {
    if (pcm_ != nullptr) snd_pcm_close(pcm_);
  }

  absl::Status Open() {
    snd_lib_error_set_handler(&QuietAlsa);
    if (int e = snd_pcm_open(&pcm_, device_.c_str(), SND_PCM_STREAM_CAPTURE, 0); e < 0) {
      pcm_ = nullptr;
      return absl::UnavailableError(
          absl::StrCat("--device ", device_, ": cannot open it for capture: ", snd_strerror(e),
                       " (`arecord -L` lists the capture devices; --input FILE plays a "
                       "recording instead)"));
    }
    unsigned int rate = 48000;
    snd_pcm_hw_params_t* hw = nullptr;
    snd_pcm_hw_params_alloca(&hw);
    snd_pcm_uframes_t period = rate / kChunksPerSecond;
    int e = snd_pcm_hw_params_any(pcm_, hw);
    if (e >= 0) e = snd_pcm_hw_params_set_access(pcm_, hw, SND_PCM_ACCESS_RW_INTERLEAVED);
    if (e >= 0) e = snd_pcm_hw_params_set_format(pcm_, hw, SND_PCM_FORMAT_S16_LE);
    if (e >= 0) e = snd_pcm_hw_params_set_channels(pcm_, hw, 1);
    if (e >= 0) e = snd_pcm_hw_params_set_rate_near(pcm_, hw, &rate, nullptr);
    if (e >= 0) {
      period = rate / kChunksPerSecond;
      e = snd_pcm_hw_params_set_period_size_near(pcm_, hw, &period, nullptr);
    }
    if (e >= 0) {
      snd_pcm_uframes_t buffer = period * 8;
      e = snd_pcm_hw_params_set_buffer_size_near(pcm_, hw, &buffer);
    }
    if (e >= 0) e = snd_pcm_hw_params(pcm_, hw);
    if (e < 0) {
      return absl::FailedPreconditionError(
          absl::StrCat("--device ", device_, ": cannot capture mono 16-bit at 48000 Hz: ",
                       snd_strerror(e)));
    }
    if (e = snd_pcm_prepare(pcm_); e < 0) {
      return absl::FailedPreconditionError(
          absl::StrCat("--device ", device_, ": cannot start capturing: ", snd_strerror(e)));
    }
    period_ = std::max<snd_pcm_uframes_t>(1, period);
    format_.sample_rate = static_cast<int>(rate);
    format_.channels = 1;
    format_.sample_format = v1::LIVE_SAMPLE_S16LE;
    format_.description = absl::StrCat("ALSA device ", device_, " (", period_, "-frame periods)");
    return absl::OkStatus();
  }

  const LiveAudioFormat& format() const override { return format_; }

  // ALSA's null device hands out silence at once; every other device waits for its samples.
  bool real_time() const override { return snd_pcm_type(pcm_) != SND_PCM_TYPE_NULL; }

  absl::StatusOr<bool> Next(std::string* bytes) override {
    bytes->resize(period_ * 2);
    for (int attempt = 0;; ++attempt) {
      const snd_pcm_sframes_t got = snd_pcm_readi(pcm_, bytes->data(), period_);
      if (got >= 0) {
        bytes->resize(static_cast<size_t>(got) * 2);
        return true;
      }
      // An overrun (-EPIPE: the stream fell behind the device) or a suspend: recover and go
      // on, as arecord does; the samples lost are lost.
      const int e = snd_pcm_recover(pcm_, static_cast<int>(got), /*silent=*/1);
      if (e < 0 || attempt >= 3) {
        return absl::UnavailableError(absl::StrCat("--device ", device_, ": capture failed: ",
                                                   snd_strerror(static_cast<int>(got))));
      }
    }
  }

 private:
  std::string device_;
  snd_pcm_t* pcm_ = nullptr;
  snd_pcm_uframes_t period_ = 480;
  LiveAudioFormat format_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<LiveAudioSource>> OpenLiveFile(const std::string& path) {
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) {
    return absl::Status(bytes.status().code(),
                        absl::StrCat("--input ", path, ": ", bytes.status().message()));
  }
  auto source = std::make_unique<FileSource>(path, *std::move(bytes));
  if (absl::Status s = source->Open(); !s.ok()) return s;
  return std::unique_ptr<LiveAudioSource>(std::move(source));
}

absl::StatusOr<std::unique_ptr<LiveAudioSource>> OpenLiveDevice(const std::string& device) {
  auto source = std::make_unique<DeviceSource>(device);
  if (absl::Status s = source->Open(); !s.ok()) return s;
  return std::unique_ptr<LiveAudioSource>(std::move(source));
}

LivePacer::LivePacer(int sample_rate, double speed)
    : sample_rate_(sample_rate), speed_(speed), start_(std::chrono::steady_clock::now()) {}

void LivePacer::WaitFor(int64_t end_frames, const std::atomic<bool>* stop) {
  if (speed_ <= 0.0) return;
  const double seconds = static_cast<double>(end_frames) / sample_rate_ / speed_;
  const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                std::chrono::duration<double>(seconds));
  while (std::chrono::steady_clock::now() < due) {
    if (stop != nullptr && stop->load()) return;
    std::this_thread::sleep_until(
        std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(10)));
  }
}

}  // namespace koma::client

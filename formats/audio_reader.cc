#include "formats/audio_reader.h"

#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"

namespace koma::formats {
namespace {

// Sample frames decoded per block: 4096 frames of up to max_channels floats (1 MB at 64).
constexpr sf_count_t kBlockFrames = 4096;

uint32_t LittleEndian(std::string_view bytes, size_t at, int width) {
  uint32_t value = 0;
  for (int i = width - 1; i >= 0; --i) {
    value = (value << 8) | static_cast<unsigned char>(bytes[at + static_cast<size_t>(i)]);
  }
  return value;
}

// Why a WAV's fmt chunk makes no recording (0 channels, 0 Hz), which libsndfile reports only
// as "SF_INFO struct incomplete"; "" when it is not a WAV or its fmt chunk says neither.
std::string WavFormatProblem(std::string_view bytes) {
  if (bytes.size() < 12 || bytes.substr(0, 4) != "RIFF" || bytes.substr(8, 4) != "WAVE") return "";
  for (size_t at = 12; at + 8 <= bytes.size();) {
    const uint32_t size = LittleEndian(bytes, at + 4, 4);
    if (bytes.substr(at, 4) == "fmt ") {
      if (at + 8 + 16 > bytes.size()) return "";  // cut short: libsndfile's words will do
      const std::string where = absl::StrCat("WAV fmt chunk at byte ", at, ": ");
      if (LittleEndian(bytes, at + 10, 2) == 0) return where + "0 channels";
      if (LittleEndian(bytes, at + 12, 4) == 0) return where + "sample rate 0 Hz";
      return "";
    }
    at += 8 + static_cast<size_t>(size) + (size & 1);  // chunks are padded to even sizes
  }
  return "";
}

// Sizes a header states for its samples that the file cannot hold. libsndfile reads what is
// there and notes the difference in its log ("data : 4294967280 (should be 384000)" for WAV,
// "SSND : ... (should be ...)" for AIFF); 0 and 0xFFFFFFFF are the placeholders of a file
// written to a pipe, whose length was unknown, and are not claims.
struct DataClaim {
  int64_t claimed = 0;  // bytes
  int64_t actual = 0;   // bytes
};

std::optional<DataClaim> ClaimInLog(SNDFILE* file) {
  std::string log(16384, '\0');
  sf_command(file, SFC_GET_LOG_INFO, log.data(), static_cast<int>(log.size()));
  for (absl::string_view line : absl::StrSplit(log.c_str(), '\n')) {
    if (!absl::StartsWith(line, "data") && !absl::StartsWith(line, "SSND")) continue;
    const size_t colon = line.find(':');
    const size_t should = line.find("(should be ");
    if (colon == absl::string_view::npos || should == absl::string_view::npos) continue;
    DataClaim claim;
    if (!absl::SimpleAtoi(absl::StripAsciiWhitespace(line.substr(colon + 1, should - colon - 1)),
                          &claim.claimed) ||
        !absl::SimpleAtoi(
            absl::StripAsciiWhitespace(absl::StripSuffix(line.substr(should + 11), ")")),
            &claim.actual)) {
      continue;
    }
    if (claim.claimed == 0 || claim.claimed == 0xFFFFFFFF || claim.claimed <= claim.actual) {
      continue;
    }
    return claim;
  }
  return std::nullopt;
}

}  // namespace

// The recording as libsndfile's virtual file: read-only, from memory.
struct AudioDecoder::Memory {
  std::string_view bytes;
  sf_count_t position = 0;

  static sf_count_t Length(void* self) {
    return static_cast<sf_count_t>(static_cast<Memory*>(self)->bytes.size());
  }
  static sf_count_t Seek(sf_count_t offset, int whence, void* self) {
    Memory* m = static_cast<Memory*>(self);
    const sf_count_t size = static_cast<sf_count_t>(m->bytes.size());
    sf_count_t base = 0;
    if (whence == SEEK_CUR) base = m->position;
    if (whence == SEEK_END) base = size;
    const sf_count_t target = base + offset;
    if (target < 0 || target > size) return -1;
    m->position = target;
    return m->position;
  }
  static sf_count_t Read(void* out, sf_count_t count, void* self) {
    Memory* m = static_cast<Memory*>(self);
    const sf_count_t size = static_cast<sf_count_t>(m->bytes.size());
    const sf_count_t n = std::max<sf_count_t>(0, std::min(count, size - m->position));
    if (n > 0) std::memcpy(out, m->bytes.data() + m->position, static_cast<size_t>(n));
    m->position += n;
    return n;
  }
  static sf_count_t Write(const void*, sf_count_t, void*) { return 0; }
  static sf_count_t Tell(void* self) { return static_cast<Memory*>(self)->position; }
};

absl::StatusOr<std::unique_ptr<AudioDecoder>> AudioDecoder::Open(std::string_view bytes,
                                                                 const AudioLimits& limits) {
  if (bytes.empty()) return absl::InvalidArgumentError("empty (0 bytes)");
  std::unique_ptr<AudioDecoder> d(new AudioDecoder());
  d->limits_ = limits;
  d->memory_ = std::make_unique<Memory>();
  d->memory_->bytes = bytes;
  SF_VIRTUAL_IO io{&Memory::Length, &Memory::Seek, &Memory::Read, &Memory::Write, &Memory::Tell};
  SF_INFO sf_info{};
  SNDFILE* file = sf_open_virtual(&io, SFM_READ, &sf_info, d->memory_.get());
  if (file == nullptr) {
    if (const std::string why = WavFormatProblem(bytes); !why.empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat(why,
                       ": a recording has at least one channel and a sample rate of 1 Hz "
                       "or more"));
    }
    return absl::InvalidArgumentError(
        absl::StrCat("not a recording libsndfile can read (WAV, FLAC, Ogg Vorbis/Opus, MP3, ...): ",
                     sf_strerror(nullptr)));
  }
  d->file_ = file;
  d->info_.sample_rate = sf_info.samplerate;
  d->info_.channels = sf_info.channels;
  d->info_.frames = sf_info.frames;
  SF_FORMAT_INFO major{}, subtype{};
  major.format = sf_info.format & SF_FORMAT_TYPEMASK;
  subtype.format = sf_info.format & SF_FORMAT_SUBMASK;
  const bool named = sf_command(nullptr, SFC_GET_FORMAT_INFO, &major, sizeof(major)) == 0 &&
                     sf_command(nullptr, SFC_GET_FORMAT_INFO, &subtype, sizeof(subtype)) == 0;
  d->info_.format = named ? absl::StrCat(major.name, " / ", subtype.name) : "unknown";
  const int sub = sf_info.format & SF_FORMAT_SUBMASK;
  d->info_.pcm16 = sub == SF_FORMAT_PCM_S8 || sub == SF_FORMAT_PCM_U8 || sub == SF_FORMAT_PCM_16;
  if (sf_info.samplerate < 1 || sf_info.samplerate > kMaxAudioSampleRate) {
    return absl::InvalidArgumentError(absl::StrCat("sample rate ", sf_info.samplerate,
                                                   " Hz is outside 1 .. ", kMaxAudioSampleRate));
  }
  if (sf_info.channels < 1) {
    return absl::InvalidArgumentError(absl::StrCat(sf_info.channels, " channels"));
  }
  if (sf_info.channels > limits.max_channels) {
    return absl::ResourceExhaustedError(absl::StrCat(
        sf_info.channels,
        " channels exceeds the server limit --max_audio_channels=", limits.max_channels));
  }
  const double claimed_s =
      static_cast<double>(sf_info.frames) / static_cast<double>(sf_info.samplerate);
  if (sf_info.frames != SF_COUNT_MAX && claimed_s > limits.max_seconds) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "the header claims ", claimed_s, " s (", sf_info.frames, " frames at ", sf_info.samplerate,
        " Hz), over the server limit --max_audio_seconds=", limits.max_seconds));
  }
  if (sf_info.frames != SF_COUNT_MAX && static_cast<double>(sf_info.frames) * sf_info.channels >
                                            static_cast<double>(limits.max_samples)) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "the header claims ", sf_info.frames, " sample frames x ", sf_info.channels,
        " channels = ", static_cast<double>(sf_info.frames) * sf_info.channels,
        " samples to decode, over the server limit --max_audio_samples=", limits.max_samples));
  }
  if (const std::optional<DataClaim> claim = ClaimInLog(file); claim && sf_info.frames > 0) {
    const double claimed_frames = static_cast<double>(sf_info.frames) *
                                  static_cast<double>(claim->claimed) /
                                  static_cast<double>(claim->actual);
    const double claimed_seconds = claimed_frames / sf_info.samplerate;
    if (claimed_seconds > limits.max_seconds) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "the header claims ", claimed_seconds, " s (", claim->claimed, " bytes of samples at ",
          sf_info.samplerate, " Hz), over the server limit --max_audio_seconds=",
          limits.max_seconds, "; the file holds ", claim->actual, " bytes"));
    }
    return absl::InvalidArgumentError(absl::StrCat("truncated: the header claims ", claim->claimed,
                                                   " bytes of samples, the file holds ",
                                                   claim->actual));
  }
  d->interleaved_.resize(static_cast<size_t>(kBlockFrames * sf_info.channels));
  d->mono_.resize(static_cast<size_t>(kBlockFrames));
  return d;
}

AudioDecoder::~AudioDecoder() {
  if (file_ != nullptr) sf_close(static_cast<SNDFILE*>(file_));
}

absl::StatusOr<int64_t> AudioDecoder::ReadBlock() {
  SNDFILE* file = static_cast<SNDFILE*>(file_);
  const sf_count_t got = sf_readf_float(file, interleaved_.data(), kBlockFrames);
  if (got < 0 || (got == 0 && sf_error(file) != SF_ERR_NO_ERROR)) {
    return absl::InvalidArgumentError(
        absl::StrCat("decoding failed after ", decoded_, " samples: ", sf_strerror(file)));
  }
  return static_cast<int64_t>(got);
}

absl::Status AudioDecoder::CheckDecodedLimits() const {
  const int channels = info_.channels;
  if (static_cast<double>(decoded_) > limits_.max_seconds * info_.sample_rate) {
    return absl::ResourceExhaustedError(
        absl::StrCat("more than ", limits_.max_seconds, " s of samples at ", info_.sample_rate,
                     " Hz, over the server limit --max_audio_seconds=", limits_.max_seconds));
  }
  if (static_cast<double>(decoded_) * channels > static_cast<double>(limits_.max_samples)) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "more than ", limits_.max_samples, " samples (", decoded_, " frames x ", channels,
        " channels) decoded, over the server limit --max_audio_samples=", limits_.max_samples));
  }
  return absl::OkStatus();
}

absl::StatusOr<absl::Span<const float>> AudioDecoder::Next() {
  absl::StatusOr<int64_t> read = ReadBlock();
  if (!read.ok()) return read.status();
  const int64_t got = *read;
  const int channels = info_.channels;
  const float scale = 1.0f / static_cast<float>(channels);
  for (int64_t f = 0; f < got; ++f) {
    const float* frame = interleaved_.data() + f * channels;
    float sum = 0.0f;
    for (int c = 0; c < channels; ++c) sum += frame[c];  // channel order: the same every run
    const float x = channels == 1 ? sum : sum * scale;
    if (!std::isfinite(x)) {
      return absl::InvalidArgumentError(
          absl::StrCat("sample frame ", decoded_ + f, " is not a finite number"));
    }
    mono_[static_cast<size_t>(f)] = x;
  }
  decoded_ += got;
  if (absl::Status s = CheckDecodedLimits(); !s.ok()) return s;
  return absl::Span<const float>(mono_.data(), static_cast<size_t>(got));
}

absl::StatusOr<absl::Span<const float>> AudioDecoder::NextInterleaved() {
  absl::StatusOr<int64_t> read = ReadBlock();
  if (!read.ok()) return read.status();
  const int64_t got = *read;
  const int channels = info_.channels;
  for (int64_t f = 0; f < got; ++f) {
    for (int c = 0; c < channels; ++c) {
      if (!std::isfinite(interleaved_[static_cast<size_t>(f * channels + c)])) {
        return absl::InvalidArgumentError(absl::StrCat("sample frame ", decoded_ + f, " channel ",
                                                       c, " is not a finite number"));
      }
    }
  }
  decoded_ += got;
  if (absl::Status s = CheckDecodedLimits(); !s.ok()) return s;
  return absl::Span<const float>(interleaved_.data(), static_cast<size_t>(got * channels));
}

}  // namespace koma::formats

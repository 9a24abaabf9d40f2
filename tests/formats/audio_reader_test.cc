// AudioDecoder on WAV files made in memory: every PCM width and float, mono mixing, blocks,
// and the bad recordings (empty, text, truncated, 0 Hz, 0 and 300 channels, a header claiming
// 100 hours, NaN samples), each refused with its reason.
#include "formats/audio_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/testing/status_matchers.h"
#include "tests/testing/wav_bytes.h"

namespace koma::formats {
namespace {

using ::koma::testing::StatusIs;
using ::koma::testing::WavBytes;
using ::koma::testing::WavHeader;
using ::testing::HasSubstr;

// Every mono sample of `bytes`, and the decoder's info.
absl::StatusOr<std::vector<float>> DecodeAll(const std::string& bytes, AudioInfo* info = nullptr,
                                             AudioLimits limits = {}) {
  absl::StatusOr<std::unique_ptr<AudioDecoder>> d = AudioDecoder::Open(bytes, limits);
  if (!d.ok()) return d.status();
  if (info != nullptr) *info = (*d)->info();
  std::vector<float> out;
  for (;;) {
    absl::StatusOr<absl::Span<const float>> block = (*d)->Next();
    if (!block.ok()) return block.status();
    if (block->empty()) break;
    out.insert(out.end(), block->begin(), block->end());
  }
  return out;
}

TEST(AudioReaderTest, EveryPcmWidthAndFloatDecodesToTheSameSamples) {
  std::vector<double> x(10000);
  for (size_t i = 0; i < x.size(); ++i) x[i] = 0.5 * std::sin(0.01 * static_cast<double>(i));
  for (const auto& [bits, is_float] : std::vector<std::pair<int, bool>>{
           {8, false}, {16, false}, {24, false}, {32, false}, {32, true}}) {
    WavHeader h;
    h.bits = bits;
    h.float_samples = is_float;
    AudioInfo info;
    absl::StatusOr<std::vector<float>> got = DecodeAll(WavBytes(h, x), &info);
    ASSERT_TRUE(got.ok()) << bits << ": " << got.status();
    ASSERT_EQ(got->size(), x.size());
    EXPECT_EQ(info.sample_rate, 16000);
    EXPECT_EQ(info.channels, 1);
    EXPECT_THAT(info.format, HasSubstr("WAV"));
    const double tolerance = bits == 8 ? 1.0 / 64 : 1e-4;
    for (size_t i = 0; i < x.size(); i += 97) EXPECT_NEAR((*got)[i], x[i], tolerance) << bits;
  }
}

TEST(AudioReaderTest, ChannelsAreMixedToTheirMean) {
  WavHeader h;
  h.channels = 3;
  std::vector<double> x;
  for (int f = 0; f < 9000; ++f) {  // more than two blocks
    x.push_back(0.5);
    x.push_back(-0.25);
    x.push_back(f % 2 ? 0.25 : 0.0);
  }
  absl::StatusOr<std::vector<float>> got = DecodeAll(WavBytes(h, x));
  ASSERT_TRUE(got.ok()) << got.status();
  ASSERT_EQ(got->size(), 9000u);
  EXPECT_NEAR((*got)[0], 0.25 / 3, 1e-4);
  EXPECT_NEAR((*got)[8999], 0.5 / 3, 1e-4);
}

TEST(AudioReaderTest, BadRecordingsAreRefusedWithTheReason) {
  const std::vector<double> second(16000, 0.1);
  EXPECT_THAT(DecodeAll("").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("empty")));
  EXPECT_THAT(DecodeAll("frame,ParamMouthOpenY\n0,0\n1,1\n").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("not a recording libsndfile can read")));
  const std::string wav = WavBytes(WavHeader{}, second);
  EXPECT_THAT(DecodeAll(wav.substr(0, 30)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("not a recording libsndfile can read")));
  WavHeader zero_hz;
  zero_hz.sample_rate = 0;
  EXPECT_THAT(DecodeAll(WavBytes(zero_hz, second)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("WAV fmt chunk at byte 12: sample rate 0 Hz: a recording has")));
  WavHeader no_channels;
  no_channels.channels = 0;
  EXPECT_THAT(DecodeAll(WavBytes(no_channels, {})).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("WAV fmt chunk at byte 12: 0 channels")));
  WavHeader many;
  many.channels = 300;
  EXPECT_THAT(DecodeAll(WavBytes(many, std::vector<double>(300 * 10, 0.1))).status(),
              StatusIs(absl::StatusCode::kResourceExhausted,
                       HasSubstr("300 channels exceeds the server limit --max_audio_channels=64")));
  AudioLimits short_limit;
  short_limit.max_seconds = 0.5;
  EXPECT_THAT(DecodeAll(wav, nullptr, short_limit).status(),
              StatusIs(absl::StatusCode::kResourceExhausted, HasSubstr("--max_audio_seconds=0.5")));
  WavHeader nan_samples;
  nan_samples.float_samples = true;
  nan_samples.bits = 32;
  EXPECT_THAT(DecodeAll(WavBytes(nan_samples, {0.1, std::nan(""), 0.1})).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("sample frame 1 is not a finite")));
}

TEST(AudioReaderTest, AHeaderClaimingHundredsOfHoursIsRefused) {
  // 100 hours of 48 kHz stereo 16-bit claimed (4 GB does not fit RIFF's 32 bits, so the
  // largest size it can state, ~6 h at these settings, stands for it) over one second of data.
  WavHeader h;
  h.sample_rate = 48000;
  h.channels = 2;
  h.data_bytes = 0xfffffff0;
  AudioLimits limits;
  limits.max_seconds = 3600;
  const absl::StatusOr<std::vector<float>> got =
      DecodeAll(WavBytes(h, std::vector<double>(96000, 0.1)), nullptr, limits);
  EXPECT_THAT(got.status(), StatusIs(absl::StatusCode::kResourceExhausted,
                                     HasSubstr("the header claims 22369.6 s (4294967280 bytes")));
  // Within the limit, a header claiming more than the file holds is a truncated file.
  limits.max_seconds = 100000;
  EXPECT_THAT(DecodeAll(WavBytes(h, std::vector<double>(96000, 0.1)), nullptr, limits).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("truncated: the header claims 4294967280 bytes of samples, the "
                                 "file holds 192000")));
  // A file written to a pipe states 0xFFFFFFFF (unknown): what is there is read.
  h.data_bytes = 0xFFFFFFFF;
  const absl::StatusOr<std::vector<float>> piped =
      DecodeAll(WavBytes(h, std::vector<double>(96000, 0.1)), nullptr, limits);
  ASSERT_TRUE(piped.ok()) << piped.status();
  EXPECT_EQ(piped->size(), 48000u);
}

}  // namespace
}  // namespace koma::formats

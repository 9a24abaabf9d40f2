// Fuzz target: any bytes as a LipBlink recording (formats/audio_reader.h), then the speech
// analysis (core/voice_activity.h), as the server runs them.
//
// The decoder must answer OK or an error status for every input, never crash, hang or read
// out of bounds (libsndfile's readers included, through koma's virtual I/O); what it decodes
// has the sample rate and channels it claims, and finite samples; the analysis of it keeps
// its invariants (sorted, disjoint speech inside the frames; a drawing per frame).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/voice_activity.h"
#include "formats/audio_reader.h"
#include "fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  koma::formats::AudioLimits limits;
  limits.max_seconds = 30;  // the fuzzer's own bound on work per input
  limits.max_samples = 4'000'000;  // ... in samples: a 1 MHz, 8-channel header is 30 s too
  absl::StatusOr<std::unique_ptr<koma::formats::AudioDecoder>> decoder =
      koma::formats::AudioDecoder::Open(bytes, limits);
  if (!decoder.ok()) {
    KOMA_FUZZ_CHECK(!decoder.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  const koma::formats::AudioInfo& info = (*decoder)->info();
  KOMA_FUZZ_CHECK(info.sample_rate >= 1 && info.sample_rate <= koma::formats::kMaxAudioSampleRate,
                  "a sample rate the grid can count");
  KOMA_FUZZ_CHECK(info.channels >= 1 && info.channels <= limits.max_channels, "channels");
  koma::FrameLoudness loudness(info.sample_rate, 24.0);
  for (;;) {
    absl::StatusOr<absl::Span<const float>> block = (*decoder)->Next();
    if (!block.ok()) return 0;
    if (block->empty()) break;
    for (float x : *block) KOMA_FUZZ_CHECK(std::isfinite(x), "finite samples");
    loudness.Add(*block);
  }
  const std::vector<double> dbfs = loudness.Dbfs(loudness.frames_touched());
  const koma::VoiceActivity v = koma::DetectVoice(dbfs, koma::VoiceOptions{});
  KOMA_FUZZ_CHECK(v.follow.size() == dbfs.size(), "a drawing per frame");
  int end = 0;
  for (const koma::FrameInterval& i : v.speech) {
    KOMA_FUZZ_CHECK(i.begin >= end && i.end > i.begin, "sorted, disjoint, non-empty speech");
    end = i.end;
  }
  KOMA_FUZZ_CHECK(end <= static_cast<int>(dbfs.size()), "speech inside the frames");
  return 0;
}

// WAV files made in memory for the audio tests: a RIFF header and the samples, written by hand
// (not through libsndfile, which reads them), so a header can also be made wrong on purpose.
#ifndef KOMA_TESTS_TESTING_WAV_BYTES_H_
#define KOMA_TESTS_TESTING_WAV_BYTES_H_

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace koma::testing {

struct WavHeader {
  int sample_rate = 16000;
  int channels = 1;
  int bits = 16;       // 8, 16, 24, 32 (PCM) or 32 with float_samples
  bool float_samples = false;
  // The data chunk's size as written; -1: the real size.
  int64_t data_bytes = -1;
};

inline void PutLe(std::string& out, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

// Interleaved samples in [-1, 1] (frames x channels) as a WAV file.
inline std::string WavBytes(const WavHeader& h, const std::vector<double>& samples) {
  std::string data;
  const int bytes = h.bits / 8;
  for (double x : samples) {
    if (h.float_samples) {
      const float f = static_cast<float>(x);
      uint32_t u;
      std::memcpy(&u, &f, 4);
      PutLe(data, u, 4);
      continue;
    }
    const double scale = std::ldexp(1.0, h.bits - 1);
    int64_t v = static_cast<int64_t>(std::lround(x * scale));
    v = std::max<int64_t>(std::min<int64_t>(v, static_cast<int64_t>(scale) - 1),
                          -static_cast<int64_t>(scale));
    if (h.bits == 8) v += 128;  // 8-bit WAV is unsigned
    PutLe(data, static_cast<uint64_t>(v), bytes);
  }
  const uint64_t data_size = h.data_bytes < 0 ? data.size() : static_cast<uint64_t>(h.data_bytes);
  std::string out = "RIFF";
  PutLe(out, 36 + data_size, 4);
  out += "WAVEfmt ";
  PutLe(out, 16, 4);
  PutLe(out, h.float_samples ? 3 : 1, 2);
  PutLe(out, static_cast<uint64_t>(h.channels), 2);
  PutLe(out, static_cast<uint64_t>(h.sample_rate), 4);
  PutLe(out, static_cast<uint64_t>(h.sample_rate) * h.channels * bytes, 4);
  PutLe(out, static_cast<uint64_t>(h.channels * bytes), 2);
  PutLe(out, static_cast<uint64_t>(h.bits), 2);
  out += "data";
  PutLe(out, data_size, 4);
  return out + data;
}

// `seconds` of a tone (amplitude `amplitude`, 220 Hz) and silence, alternating as listed:
// {{0.5, 0.3}, {0.2, 0}} is half a second of tone then 0.2 s of silence.
inline std::vector<double> ToneAndSilence(int sample_rate,
                                          const std::vector<std::pair<double, double>>& parts) {
  std::vector<double> out;
  for (const auto& [seconds, amplitude] : parts) {
    const int n = static_cast<int>(seconds * sample_rate + 0.5);
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(out.size()) / sample_rate;
      out.push_back(amplitude * std::sin(2 * 3.14159265358979 * 220 * t));
    }
  }
  return out;
}

// The same parts, but voice-like where ToneAndSilence holds a tone (a held tone is music, not
// speech: docs/semantics.md, "Voice, not sound"): 12 harmonics of a pitch gliding between 100
// and 180 Hz three times a second, their loudest harmonic (a formant) sweeping from the 1st to
// the 9th 2.5 times a second, scaled to a sine's RMS at `amplitude` (amplitude / sqrt 2).
inline std::vector<double> VoiceLikeAndSilence(
    int sample_rate, const std::vector<std::pair<double, double>>& parts) {
  constexpr double kPi = 3.14159265358979;
  constexpr int kHarmonics = 12;
  std::vector<double> out;
  double phase = 0.0;  // of the fundamental, radians
  for (const auto& [seconds, amplitude] : parts) {
    const int n = static_cast<int>(seconds * sample_rate + 0.5);
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(out.size()) / sample_rate;
      phase += 2 * kPi * (140 + 40 * std::sin(2 * kPi * 3 * t)) / sample_rate;
      const double formant = 5 + 4 * std::sin(2 * kPi * 2.5 * t);
      double sum = 0.0, weights = 0.0;
      for (int h = 1; h <= kHarmonics; ++h) {
        const double w = 1.0 / (1.0 + (h - formant) * (h - formant));
        sum += w * std::sin(h * phase);
        weights += w * w;
      }
      out.push_back(amplitude * sum / std::sqrt(weights));
    }
  }
  return out;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_WAV_BYTES_H_

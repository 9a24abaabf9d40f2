// The voice features and the speech gate (issue 44, "Voice, not sound"): SmallFft and RealFft
// against a naive DFT, the features against a naive reference (every lag's sums from scratch, no
// sliding, no decimation shortcuts), the same bits for any block split (what a streaming
// analysis relies on), the grid of FrameLoudness, what tones, noise and a moving voice-like
// signal give, and the gate's rules worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/small_fft.h"
#include "core/split_mix64.h"
#include "core/voice_activity.h"
#include "core/voice_features.h"
#include "core/voice_gate.h"

namespace koma {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(SmallFftTest, MatchesANaiveDft) {
  for (int n : {2, 4, 8, 64, 256, 4096}) {
    SmallFft fft(n);
    for (int k = 0; k < n; ++k) {
      ASSERT_NEAR(fft.Cos(k), std::cos(2 * kPi * k / n), 1e-12) << n << " " << k;
      ASSERT_NEAR(fft.Sin(k), std::sin(2 * kPi * k / n), 1e-12) << n << " " << k;
    }
    if (n > 256) continue;
    SplitMix64 rng(static_cast<uint64_t>(n));
    std::vector<double> re(n), im(n);
    for (int t = 0; t < n; ++t) re[t] = rng.Unit() - 0.5, im[t] = rng.Unit() - 0.5;
    std::vector<double> out_re = re, out_im = im;
    fft.Forward(absl::MakeSpan(out_re), absl::MakeSpan(out_im));
    for (int k = 0; k < n; ++k) {
      double sr = 0, si = 0;
      for (int t = 0; t < n; ++t) {
        const double a = -2 * kPi * k * t / n;
        sr += re[t] * std::cos(a) - im[t] * std::sin(a);
        si += re[t] * std::sin(a) + im[t] * std::cos(a);
      }
      EXPECT_NEAR(out_re[k], sr, 1e-9) << n << " " << k;
      EXPECT_NEAR(out_im[k], si, 1e-9) << n << " " << k;
    }
  }
}

TEST(SmallFftTest, RealFftMatchesANaiveDft) {
  for (int n : {4, 8, 64, 256}) {
    RealFft fft(n);
    SplitMix64 rng(static_cast<uint64_t>(n) + 1);
    std::vector<double> x(n);
    for (double& v : x) v = rng.Unit() - 0.5;
    std::vector<double> re(n / 2 + 1), im(n / 2 + 1);
    fft.Forward(x, absl::MakeSpan(re), absl::MakeSpan(im));
    for (int k = 0; k <= n / 2; ++k) {
      double sr = 0, si = 0;
      for (int t = 0; t < n; ++t) {
        sr += x[t] * std::cos(-2 * kPi * k * t / n);
        si += x[t] * std::sin(-2 * kPi * k * t / n);
      }
      EXPECT_NEAR(re[k], sr, 1e-9) << n << " " << k;
      EXPECT_NEAR(im[k], si, 1e-9) << n << " " << k;
    }
  }
}

std::vector<float> Tone(int rate, double seconds, double hz, double amplitude) {
  std::vector<float> x(static_cast<size_t>(rate * seconds));
  for (size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<float>(amplitude * std::sin(2 * kPi * hz * static_cast<double>(i) / rate));
  }
  return x;
}

std::vector<float> Noise(int rate, double seconds, double amplitude, uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<float> x(static_cast<size_t>(rate * seconds));
  for (float& v : x) v = static_cast<float>(amplitude * (2 * rng.Unit() - 1));
  return x;
}

std::vector<VoiceFrame> Features(const std::vector<float>& x, int rate, double fps,
                                 size_t block) {
  VoiceFeatures f(rate, fps);
  for (size_t i = 0; i < x.size(); i += block) {
    f.Add(absl::MakeConstSpan(x.data() + i, std::min(block, x.size() - i)));
  }
  f.Finish();
  return f.frames();
}

// The reference voicing of frame g: the pre-emphasised decimated signal written out whole,
// the window [end - w, end), every lag's three sums from scratch in one running sum each (the
// fast one slides the lag's sum of squares and splits each sum in four).
double NaiveVoicing(const std::vector<float>& x, int rate, int64_t first, int64_t next) {
  const int factor = std::max(1, rate / 6000), r = rate / factor;
  std::vector<double> d;
  for (size_t i = 0; i + factor <= x.size(); i += factor) {
    double s = 0;
    for (int k = 0; k < factor; ++k) s += x[i + k];
    d.push_back(s / factor);
  }
  std::vector<double> y(d.size());
  for (size_t j = 0; j < d.size(); ++j) y[j] = d[j] - (j ? d[j - 1] : 0.0);
  const int64_t end = next / factor, begin = first / factor;
  const int w = static_cast<int>(std::clamp<int64_t>(end - begin, r / 24, r / 12));
  const auto at = [&](int64_t j) { return j < 0 ? 0.0 : y[static_cast<size_t>(j)]; };
  double e0 = 0;
  for (int64_t n = end - w; n < end; ++n) e0 += at(n) * at(n);
  if (!(e0 > 1e-20 * w)) return 0.0;
  double best = -2;
  for (int lag = std::max(2, r / 400); lag <= (r + 59) / 60; ++lag) {
    double dot = 0, e = 0;
    for (int64_t n = end - w; n < end; ++n) dot += at(n) * at(n - lag), e += at(n - lag) * at(n - lag);
    if (e > 0) best = std::max(best, dot / std::sqrt(e0 * e));
  }
  return std::clamp(best, -1.0, 1.0);
}

TEST(VoiceFeaturesTest, VoicingMatchesTheNaiveReference) {
  for (int rate : {8000, 16000, 22050, 48000}) {
    std::vector<float> x = Tone(rate, 1.0, 130.0, 0.3);
    const std::vector<float> n = Noise(rate, 1.0, 0.2, static_cast<uint64_t>(rate));
    for (size_t i = 0; i < x.size(); ++i) x[i] += (i > x.size() / 2) ? n[i] : 0.0f;
    const std::vector<VoiceFrame> f = Features(x, rate, 24, 1000);
    const GridSamples grid(rate, 24);
    for (int g = 1; g + 1 < static_cast<int>(f.size()); ++g) {
      EXPECT_NEAR(f[g].voicing, NaiveVoicing(x, rate, grid.FirstSample(g),
                                             grid.FirstSample(g + 1)), 1e-9)
          << rate << " " << g;
    }
  }
}

TEST(VoiceFeaturesTest, AnyBlockSplitGivesTheSameBitsAndFrameLoudnessFrames) {
  SplitMix64 rng(3);
  for (int trial = 0; trial < 12; ++trial) {
    const int rate = std::vector<int>{8000, 11025, 16000, 44100, 48000}[rng.Int(0, 4)];
    const double fps = std::vector<double>{24, 30, 24000.0 / 1001, 60, 12}[rng.Int(0, 4)];
    std::vector<float> x = Noise(rate, 0.2 + rng.Unit(), 0.1, trial);
    const std::vector<float> t = Tone(rate, 2.0, 100 + 200 * rng.Unit(), 0.4);
    for (size_t i = 0; i < x.size(); ++i) x[i] += t[i];
    const std::vector<VoiceFrame> whole = Features(x, rate, fps, x.size());
    FrameLoudness loudness(rate, fps);
    loudness.Add(x);
    ASSERT_EQ(static_cast<int>(whole.size()), loudness.frames_touched()) << rate << " " << fps;
    for (size_t block : {1, 7, 160, 4096}) {
      const std::vector<VoiceFrame> split = Features(x, rate, fps, block);
      ASSERT_EQ(split.size(), whole.size());
      for (size_t g = 0; g < whole.size(); ++g) {
        // Bit for bit: the same operations in the same order, whatever the blocks.
        ASSERT_EQ(split[g].voicing, whole[g].voicing) << block << " " << g;
        ASSERT_EQ(split[g].change, whole[g].change) << block << " " << g;
        ASSERT_EQ(split[g].pitch_hz, whole[g].pitch_hz) << block << " " << g;
      }
    }
  }
}

TEST(VoiceFeaturesTest, FramesAreDecidedWithoutLookahead) {
  // Frame g is decided once the first sample of frame g + 1 has arrived (and the decimated
  // sample it completes: at most rate / 6000 - 1 samples later).
  const int rate = 48000;  // 2000 samples per 24 fps frame, decimated by 8
  VoiceFeatures f(rate, 24);
  const std::vector<float> x = Tone(rate, 1.0, 200, 0.5);
  f.Add(absl::MakeConstSpan(x.data(), 2000 * 5));
  EXPECT_EQ(f.frames().size(), 5u);
  f.Add(absl::MakeConstSpan(x.data() + 10000, 8));
  EXPECT_EQ(f.frames().size(), 5u);  // frame 5 needs its samples
  f.Finish();
  EXPECT_EQ(f.frames().size(), 6u);  // the partial frame 5, at the end
}

TEST(VoiceFeaturesTest, ATonesIsVoicedAndSteadyNoiseIsNot) {
  for (int rate : {16000, 48000}) {
    const std::vector<VoiceFrame> tone = Features(Tone(rate, 1.0, 220, 0.5), rate, 24, 512);
    for (size_t g = 3; g < tone.size(); ++g) {
      EXPECT_GT(tone[g].voicing, 0.95) << g;
      EXPECT_NEAR(tone[g].pitch_hz, 220, 220 * 0.03) << g;
      EXPECT_LT(tone[g].change, 0.01) << g;
    }
    const std::vector<VoiceFrame> noise = Features(Noise(rate, 1.0, 0.3, 9), rate, 24, 512);
    for (size_t g = 3; g < noise.size(); ++g) EXPECT_LT(noise[g].voicing, 0.3) << g;
    const std::vector<VoiceFrame> silence =
        Features(std::vector<float>(rate / 2, 0.0f), rate, 24, 512);
    for (const VoiceFrame& f : silence) {
      EXPECT_EQ(f.voicing, 0.0);
      EXPECT_EQ(f.change, 1.0);
    }
  }
  // 2 kHz cannot show a 400 Hz pitch: unusable, and the gate lets everything through.
  VoiceFeatures low(2000, 24);
  EXPECT_FALSE(low.usable());
  const std::vector<float> x = Tone(2000, 1.0, 100, 0.5);
  low.Add(x);
  low.Finish();
  EXPECT_EQ(VoiceLikeStretches(low, 24, VoiceGateOptions{}),
            (std::vector<FrameInterval>{{0, 24}}));
}

// Frames by hand: 'v' voice-like (voiced, changing), 'h' held (voiced, steady), 'u' unvoiced
// and changing, '.' silent.
std::vector<VoiceFrame> Frames(const std::string& s) {
  std::vector<VoiceFrame> out;
  for (char c : s) {
    VoiceFrame f;
    f.voicing = (c == 'v' || c == 'h') ? 0.8 : c == 'u' ? 0.1 : 0.0;
    f.change = c == 'h' ? 0.02 : c == '.' ? 1.0 : 0.5;
    out.push_back(f);
  }
  return out;
}

TEST(VoiceGateTest, HandWorkedStretches) {
  const VoiceGateOptions o;  // at 24 fps: gap 7, at least 4 frames, density 0.4, reach 4
  // Six voice-like frames 3 and 5 frames apart over 12 frames: one stretch, reaching 4
  // unvoiced frames out on each side.
  EXPECT_EQ(VoiceLikeStretches(Frames("......uuuuuvvuuvvuuuuvvuuuuuu"), 1, 24, o),
            (std::vector<FrameInterval>{{7, 27}}));
  // Three voice-like frames are not enough.
  EXPECT_EQ(VoiceLikeStretches(Frames("....vuuuvuuuvuuuu"), 1, 24, o),
            std::vector<FrameInterval>{});
  // A held note stops the reach: two held frames in a row; one alone does not.
  // (The first 'v' after a held frame is not voice-like: the frame before it did not change.)
  EXPECT_EQ(VoiceLikeStretches(Frames("hhhhhhvvvvvhuuuuuhh"), 1, 24, o),
            (std::vector<FrameInterval>{{6, 15}}));
  // A note's onset changes the spectrum once: voiced, then held; never a stretch.
  EXPECT_EQ(VoiceLikeStretches(Frames("hhhvhhhvhhhvhhhvhhhvhhhvhhh"), 1, 24, o),
            std::vector<FrameInterval>{});
  // Sparse: 5 voice-like frames over 17 (density 0.29).
  EXPECT_EQ(VoiceLikeStretches(Frames("vvuuuuuuvvuuuuuuvvhh"), 1, 24, o),
            (std::vector<FrameInterval>{}));
  VoiceGateOptions off;
  off.enabled = false;
  EXPECT_EQ(VoiceLikeStretches(Frames("hhhhhh"), 1, 24, off),
            (std::vector<FrameInterval>{{0, 6}}));
}

TEST(VoiceGateTest, IntersectAndDetectVoiceCutToTheStretches) {
  EXPECT_EQ(Intersect(std::vector<FrameInterval>{{0, 10}, {20, 30}},
                      std::vector<FrameInterval>{{5, 22}, {29, 40}}),
            (std::vector<FrameInterval>{{5, 10}, {20, 22}, {29, 30}}));
  // Loud [10, 40) and [50, 60) over a -60 dBFS floor; voice-like [16, 30), [33, 36), [58, 59).
  std::vector<double> db(70, -60.0);
  for (int g = 10; g < 40; ++g) db[g] = -20.0;
  for (int g = 50; g < 60; ++g) db[g] = -20.0;
  EXPECT_EQ(DetectVoice(db, VoiceOptions{}).speech,
            (std::vector<FrameInterval>{{10, 40}, {50, 60}}));
  const std::vector<FrameInterval> gate = {{16, 30}, {33, 36}, {58, 59}};
  // Kept tails of at most 4 frames: the 6 before [16, 30) are cut, the gap of 3 between the
  // two stretches and the 4 after [33, 36) kept; [50, 60) keeps its 1-frame stretch's
  // neighbours (8 before: cut; 1 after: kept), [58, 60), 2 frames: long enough.
  VoiceActivity v = DetectVoice(db, VoiceOptions{}, &gate);
  EXPECT_EQ(v.speech, (std::vector<FrameInterval>{{16, 40}, {58, 60}}));
  EXPECT_EQ(v.follow[15], MouthShape::kClosed);
  EXPECT_NE(v.follow[16], MouthShape::kClosed);
  // No tails kept: the stretches exactly, and [58, 59) too short (min_speech_frames 2).
  VoiceOptions strict;
  strict.keep_tail_frames = 0;
  EXPECT_EQ(DetectVoice(db, strict, &gate).speech,
            (std::vector<FrameInterval>{{16, 30}, {33, 36}}));
  // No stretch at all: no speech.
  const std::vector<FrameInterval> none;
  EXPECT_TRUE(DetectVoice(db, VoiceOptions{}, &none).speech.empty());
}

TEST(VoiceGateTest, ValidatesItsOptions) {
  VoiceOptions o;
  o.gate.min_voicing = 1.5;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "min_voicing: 1.5 must be in [0, 1]");
  o.gate = {};
  o.gate.reach_s = -1;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "reach_s: -1 must be in [0, 10] s");
  o.gate = {};
  o.keep_tail_frames = -1;
  EXPECT_EQ(ValidateVoiceOptions(o).message(), "keep_tail_frames: -1 must be >= 0");
}

}  // namespace
}  // namespace koma

#include "core/voice_features.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace koma {
namespace {

// The signal is averaged down to 6 to 12 kHz (factor = rate / 6000 samples): enough for the
// pitch and the first formants, and a pitch search of ~20x cheaper at 48 kHz.
constexpr int kDecimatedRate = 6000;
// Below this decimated rate a 400 Hz pitch period is under 10 samples: no useful voicing.
constexpr int kMinUsableRate = 4000;
// Pitch periods searched: 1/400 .. 1/60 s (voices from a deep male one to a child's).
constexpr int kMaxPitchHz = 400;
constexpr int kMinPitchHz = 60;
// The autocorrelation's window ends at the frame's end and spans the frame, within 1/24 and
// 1/12 s: a 60 fps grid still sees a pitch period several times, a 1 fps grid's memory stays
// bounded.
constexpr int kMinWindowPerSecond = 24;
constexpr int kMaxWindowPerSecond = 12;
// The spectrum: 256 points, 21 to 43 ms at the decimated rate, ending at the frame's end.
constexpr int kSpectrumSize = 256;
// The grid rate whose one frame `change` compares across, frames per second.
constexpr double kChangeFps = 24.0;
// The pitch's lag: the shortest within this of the best correlation.
constexpr double kPitchSlack = 0.02;
// Mean square of the pre-emphasised signal below which a frame is silent (-200 dB).
constexpr double kSilentMeanSquare = 1e-20;

// sum a[n] b[n] over n < count in eight interleaved partial sums s0 .. s7 (n mod 8), added as
// ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7)) at the end: a fixed order, so the same
// bits everywhere, that keeps eight products in flight instead of waiting on one running sum
// (the pitch search is most of the features' time). The sums live in pairs of GCC/Clang
// vector lanes: SSE2 on x86-64, NEON on ARM, scalar code elsewhere, each lane's + and x the
// same IEEE operations.
using Pair = double __attribute__((vector_size(16)));

Pair Load(const double* p) {
  Pair v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

double Dot(const double* a, const double* b, int count) {
  Pair s01 = {0.0, 0.0}, s23 = {0.0, 0.0}, s45 = {0.0, 0.0}, s67 = {0.0, 0.0};
  int n = 0;
  for (; n + 8 <= count; n += 8) {
    s01 += Load(a + n) * Load(b + n);
    s23 += Load(a + n + 2) * Load(b + n + 2);
    s45 += Load(a + n + 4) * Load(b + n + 4);
    s67 += Load(a + n + 6) * Load(b + n + 6);
  }
  double s0 = s01[0];
  for (; n < count; ++n) s0 += a[n] * b[n];
  return ((s0 + s01[1]) + (s23[0] + s23[1])) + ((s45[0] + s45[1]) + (s67[0] + s67[1]));
}

}  // namespace

VoiceFeatures::VoiceFeatures(int sample_rate, double frame_fps)
    : grid_(sample_rate, frame_fps), fft_(kSpectrumSize) {
  factor_ = std::max(1, sample_rate / kDecimatedRate);
  const int rate = sample_rate / factor_;  // integer part: only sizes depend on it
  rate_ = static_cast<double>(sample_rate) / factor_;
  usable_ = rate >= kMinUsableRate;
  min_lag_ = std::max(2, rate / kMaxPitchHz);
  max_lag_ = std::max(min_lag_, (rate + kMinPitchHz - 1) / kMinPitchHz);
  min_window_ = std::max(1, rate / kMinWindowPerSecond);
  max_window_ = std::max(min_window_, rate / kMaxWindowPerSecond);
  step_ = std::max(1, static_cast<int>(std::floor(frame_fps / kChangeFps + 0.5)));
  hann_.resize(kSpectrumSize);
  const SmallFft turns(kSpectrumSize);  // cos(2 pi t / n), deterministic
  for (int t = 0; t < kSpectrumSize; ++t) hann_[t] = 0.5 - 0.5 * turns.Cos(t);
  spectra_.assign(static_cast<size_t>(step_), {});
  windowed_.resize(kSpectrumSize);
  re_.resize(kSpectrumSize / 2 + 1);
  im_.resize(kSpectrumSize / 2 + 1);
  next_end_ = grid_.FirstSample(1) / factor_;
}

double VoiceFeatures::Y(int64_t j) const {
  return j < base_ ? 0.0 : y_[static_cast<size_t>(j - base_)];
}

void VoiceFeatures::Add(absl::Span<const float> mono) {
  samples_ += static_cast<int64_t>(mono.size());
  size_t i = 0;
  while (i < mono.size()) {
    // Each decimated sample sums its `factor_` samples in sample order, whatever the blocks.
    // First the one begun in an earlier block, then this block's whole ones into `means_`
    // (their sums do not wait on each other), then the start of the next.
    if (block_count_ > 0 || mono.size() - i < static_cast<size_t>(factor_)) {
      const size_t take =
          std::min(mono.size() - i, static_cast<size_t>(factor_ - block_count_));
      for (size_t k = 0; k < take; ++k) block_sum_ += mono[i + k];
      i += take;
      block_count_ += static_cast<int>(take);
      if (block_count_ == factor_) {
        Decimated(block_sum_ / factor_);
        block_sum_ = 0.0;
        block_count_ = 0;
      }
      continue;
    }
    const size_t whole = (mono.size() - i) / static_cast<size_t>(factor_);
    means_.resize(whole);
    for (size_t b = 0; b < whole; ++b) {
      double sum = 0.0;
      for (int k = 0; k < factor_; ++k) sum += mono[i + b * factor_ + k];
      means_[b] = sum / factor_;
    }
    for (const double d : means_) Decimated(d);
    i += whole * static_cast<size_t>(factor_);
  }
}

void VoiceFeatures::Decimated(double d) {
  // Pre-emphasis (the first difference): brown and pink noise, whose power sits at the lowest
  // frequencies, would otherwise correlate with themselves at any short lag like a tone.
  y_.push_back(d - last_);
  last_ = d;
  ++decimated_;
  if (!usable_) {
    y_.clear();
    base_ = decimated_;
  }
  while (decimated_ >= next_end_) {
    Decide(decided(), next_end_);
    next_end_ = grid_.FirstSample(decided() + 1) / factor_;
  }
  // Keep what the next windows reach back to, and drop the rest in large steps.
  const int64_t keep = std::max<int64_t>(max_window_ + max_lag_, kSpectrumSize) + 1;
  if (static_cast<int64_t>(y_.size()) > 4 * keep) {
    const int64_t drop = static_cast<int64_t>(y_.size()) - keep;
    y_.erase(y_.begin(), y_.begin() + drop);
    base_ += drop;
  }
}

void VoiceFeatures::Finish() {
  if (block_count_ > 0) {  // the last, partial decimated sample: the mean of what there is
    Decimated(block_sum_ / block_count_);
    block_sum_ = 0.0;
    block_count_ = 0;
  }
  while (grid_.FirstSample(decided()) < samples_) Decide(decided(), decimated_);
}

void VoiceFeatures::TakeFrames(std::vector<VoiceFrame>& into) {
  into.clear();
  into.swap(frames_);
  taken_ += static_cast<int64_t>(into.size());
}

void VoiceFeatures::Decide(int64_t frame, int64_t end) {
  VoiceFrame out;
  if (!usable_) {
    frames_.push_back(out);
    return;
  }
  const int64_t begin = grid_.FirstSample(frame) / factor_;
  const int window = static_cast<int>(
      std::clamp<int64_t>(end - begin, min_window_, max_window_));
  // The window and the lags it reaches back to, as one contiguous run (zeros before the start).
  const int span = window + max_lag_;
  std::vector<double>& seg = segment_;
  seg.resize(static_cast<size_t>(span));
  for (int k = 0; k < span; ++k) seg[k] = Y(end - span + k);
  const double* now = seg.data() + max_lag_;  // now[0 .. window) is the frame's window
  const double e0 = Dot(now, now, window);
  if (e0 > kSilentMeanSquare * window) {
    // The sum of squares of now[n - lag], slid one lag at a time.
    double e_lag = Dot(now - min_lag_, now - min_lag_, window);
    double best = -2.0;
    r_.assign(static_cast<size_t>(max_lag_ - min_lag_ + 1), -2.0);
    for (int lag = min_lag_; lag <= max_lag_; ++lag) {
      const double* then = now - lag;
      const double dot = Dot(now, then, window);
      if (e_lag > 0.0) {
        const double r = dot / std::sqrt(e0 * e_lag);
        r_[lag - min_lag_] = r;
        best = std::max(best, r);
      }
      if (lag < max_lag_) e_lag += then[-1] * then[-1] - then[window - 1] * then[window - 1];
    }
    if (best > -2.0) {
      out.voicing = std::clamp(best, -1.0, 1.0);
      // The pitch: the shortest lag nearly as good as the best (a period's multiples
      // correlate as well, and the integer lags favour one of them by chance).
      int lag = min_lag_;
      while (r_[lag - min_lag_] < best - kPitchSlack) ++lag;
      // Between the integer lags: the peak of the parabola through the lag and its neighbours.
      double offset = 0.0;
      if (lag > min_lag_ && lag < max_lag_) {
        const double a = r_[lag - min_lag_ - 1], b = r_[lag - min_lag_], c = r_[lag - min_lag_ + 1];
        const double curve = a - 2.0 * b + c;
        if (curve < 0.0) offset = std::clamp(0.5 * (a - c) / curve, -0.5, 0.5);
      }
      out.pitch_hz = rate_ / (lag + offset);
    }
  }
  // The magnitude spectrum of the last kSpectrumSize samples, Hann-windowed.
  for (int t = 0; t < kSpectrumSize; ++t) windowed_[t] = Y(end - kSpectrumSize + t) * hann_[t];
  fft_.Forward(windowed_, absl::MakeSpan(re_), absl::MakeSpan(im_));
  std::vector<double>& slot = spectra_[static_cast<size_t>(frame % step_)];
  std::vector<double> magnitude(kSpectrumSize / 2 + 1);
  for (int k = 0; k <= kSpectrumSize / 2; ++k) {
    magnitude[k] = std::sqrt(re_[k] * re_[k] + im_[k] * im_[k]);
  }
  if (!slot.empty()) {  // the spectrum `step_` frames earlier
    double dot = 0.0, a = 0.0, b = 0.0;
    for (int k = 0; k <= kSpectrumSize / 2; ++k) {
      dot += magnitude[k] * slot[k];
      a += magnitude[k] * magnitude[k];
      b += slot[k] * slot[k];
    }
    if (a > 0.0 && b > 0.0) out.change = std::clamp(1.0 - dot / std::sqrt(a * b), 0.0, 1.0);
  }
  slot = std::move(magnitude);
  frames_.push_back(out);
}

}  // namespace koma

// What tells a speaking voice from music and noise, per film-grid frame (docs/semantics.md,
// "Voice, not sound"): how periodic the frame is (voicing: speech's vowels and music's notes
// are, noise is not) and how much its spectrum changed since ~1/24 s earlier (a voice's
// formants and pitch keep moving, a held note or chord does not). Computed causally from
// sample blocks as they arrive (Add, like FrameLoudness), so a streaming analysis can reuse it:
// frame g's features are decided as soon as the first sample of frame g + 1 has arrived (no
// lookahead), and the state is bounded (the last ~0.1 s of the signal and a few spectra),
// whatever the recording's length. Deterministic: + - * / and sqrt only, in a fixed order, and
// core/small_fft.h's spectrum.
#ifndef KOMA_CORE_VOICE_FEATURES_H_
#define KOMA_CORE_VOICE_FEATURES_H_

#include <cstdint>
#include <vector>

#include "absl/types/span.h"
#include "core/grid_samples.h"
#include "core/small_fft.h"

namespace koma {

struct VoiceFrame {
  // The largest normalised autocorrelation of the frame's pre-emphasised signal at a pitch
  // period of 1/400 .. 1/60 s, in [-1, 1] (0 for a silent frame): about 1 for a held note,
  // 0.2 to 0.9 for speech's voiced frames, below 0.2 for pink or brown noise.
  double voicing = 0.0;
  // 1 - the cosine similarity of the frame's magnitude spectrum with the one `step` frames
  // earlier (VoiceFeatures::step()), in [0, 1]; 1 when either is silent.
  double change = 1.0;
  // The pitch, Hz: the shortest lag within 0.02 of the best correlation, between integer lags
  // by a parabola through its neighbours (0 for a silent frame).
  double pitch_hz = 0.0;
};

class VoiceFeatures {
 public:
  // The grid of FrameLoudness: sample_rate in 1 .. 1e6 per second, frame_fps in (0, 1000].
  VoiceFeatures(int sample_rate, double frame_fps);

  void Add(absl::Span<const float> mono);
  // The recording ends: the frames it reaches into (the last may be partial) are decided.
  void Finish();

  // Frames decided and not yet taken, from frame decided() - frames().size().
  const std::vector<VoiceFrame>& frames() const { return frames_; }
  // Moves the frames of frames() into `into` (cleared first; its buffer is reused for the
  // next ones, so a live stream's state stays bounded without allocating: core/live_voice.h).
  // The frame numbering goes on.
  void TakeFrames(std::vector<VoiceFrame>& into);
  // Frames decided so far, taken or not.
  int64_t decided() const { return taken_ + static_cast<int64_t>(frames_.size()); }
  // Whether the rate can show a pitch up to 400 Hz (>= 4 kHz); below it every frame keeps
  // the defaults and the speech gate lets everything through (core/voice_gate.h).
  bool usable() const { return usable_; }
  // The frames between the two spectra `change` compares: round(frame_fps / 24), >= 1, so the
  // comparison spans about 1/24 s at any grid rate.
  int step() const { return step_; }

 private:
  void Decimated(double d);
  void Decide(int64_t frame, int64_t end);
  double Y(int64_t j) const;  // the pre-emphasised signal at decimated index j (0 before 0)

  GridSamples grid_;
  bool usable_ = false;
  int factor_ = 1;            // samples averaged into one decimated sample
  double rate_ = 1.0;         // decimated samples per second
  int min_lag_ = 1, max_lag_ = 1;  // pitch periods, decimated samples
  int min_window_ = 1, max_window_ = 1;  // the autocorrelation's window, decimated samples
  int step_ = 1;
  RealFft fft_;
  std::vector<double> hann_;  // the spectrum's window

  int64_t samples_ = 0;       // original samples seen
  double block_sum_ = 0.0;    // the decimated sample being summed
  int block_count_ = 0;
  double last_ = 0.0;         // the previous decimated sample (pre-emphasis)
  std::vector<double> y_;     // the pre-emphasised signal from decimated index base_ on
  int64_t base_ = 0;
  int64_t decimated_ = 0;     // decimated samples produced
  int64_t next_end_ = 0;      // the first decimated index past frame frames_.size()
  std::vector<std::vector<double>> spectra_;  // the last step() magnitude spectra, a ring
  // Scratch, reused block to block.
  std::vector<double> windowed_, re_, im_, segment_, r_, means_;
  std::vector<VoiceFrame> frames_;
  int64_t taken_ = 0;         // frames moved out by TakeFrames
};

}  // namespace koma

#endif  // KOMA_CORE_VOICE_FEATURES_H_

// Speech from a recording, on the film grid (docs/semantics.md, "LipBlink from a voice"): the
// loudness of each grid frame (RMS in dBFS over the frame's samples), the speech intervals
// (frames well above the estimated noise floor, short gaps bridged, short bursts dropped), and
// for MOUTH_FOLLOW the drawing each frame's loudness asks for, with hysteresis. Plain arrays in,
// plain arrays out: decoding the recording is formats/audio_reader.h's job, and it hands the
// samples over in blocks, so memory grows with the grid frames, not with the samples.
#ifndef KOMA_CORE_VOICE_ACTIVITY_H_
#define KOMA_CORE_VOICE_ACTIVITY_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/types/span.h"
#include "core/film_grid.h"
#include "core/grid_samples.h"
#include "core/lip_blink.h"
#include "core/voice_gate.h"

namespace koma {

// The loudness of digital silence (and of any frame below it): 10 log10(1e-15), dBFS.
inline constexpr double kSilenceDbfs = -150.0;
// The unset stay threshold: this fraction of the recording's range above its floor, and at
// least kMinStayAboveFloorDb (VoiceOptions::stay_above_floor_db).
inline constexpr double kStayFractionOfRange = 0.2;
inline constexpr double kMinStayAboveFloorDb = 2.0;

// 10 log10(mean_square) in dB (full scale: a mean square of 1 is 0 dBFS), kSilenceDbfs at or
// below 1e-15. Deterministic: frexp and + - * / only (libm's log10 may differ in its last bit
// between machines, and a threshold comparison on it would then differ too). Within 1e-12 dB
// of the exact value.
double MeanSquareToDbfs(double mean_square);

// Mono samples (full scale +-1) in blocks -> the mean square of each analysis frame. Frame g
// (at `frame_fps`, the film grid's rate) holds samples [first(g), first(g + 1)) of
// core/grid_samples.h: the same on every machine, no drift over an hour. Sums run in sample
// order.
class FrameLoudness {
 public:
  // sample_rate in 1 .. 1e6 samples per second, frame_fps in (0, 1000] frames per second.
  FrameLoudness(int sample_rate, double frame_fps);

  void Add(absl::Span<const float> mono);

  int64_t samples() const { return samples_; }
  // Frames the samples reach into (the last one may be partial): 0 for no samples.
  int frames_touched() const { return static_cast<int>(sums_.size()); }

  // RMS in dBFS per frame 0 .. frames - 1: a partial last frame over the samples it has,
  // frames past the recording kSilenceDbfs.
  std::vector<double> Dbfs(int frames) const;

 private:
  GridSamples grid_;
  std::vector<double> sums_;      // per frame touched: the sum of squares
  std::vector<int64_t> counts_;   // per frame touched: samples summed
  int64_t samples_ = 0;
  int64_t next_boundary_ = 0;     // first sample of frame sums_.size()
};

struct VoiceOptions {
  // The noise floor: given (dBFS), or this percentile of the frames' loudness (0 < p < 100):
  // the quietest tenth of an ordinary dialogue take is its room noise.
  std::optional<double> noise_floor_dbfs;
  double noise_percentile = 10.0;
  // A speech interval is a run of frames at least `stay_above_floor_db` above the floor holding
  // one frame at least `start_above_floor_db` above it (0 < stay <= start, dB). Unset stay:
  // kStayFractionOfRange of the recording's range (its frames' 90th percentile minus the
  // floor), within [2 dB, start]: a clean take's noise bursts beside a word stay out, a noisy
  // take's soft word ends stay in. Neither threshold goes below `min_speech_dbfs`, so a clean
  // recording's digital silence (floor -150) does not make its faintest breath speech.
  double start_above_floor_db = 9.0;
  std::optional<double> stay_above_floor_db;
  double min_speech_dbfs = -55.0;
  // Gaps of at most `bridge_gap_frames` frames between intervals are bridged (a stop
  // consonant's closure, a breath between words: up to 125 ms on the 24 fps grid). Longer
  // gaps of at most `faint_gap_frames` are bridged too when none of their frames falls to
  // within `pause_above_floor_db` of the noise floor: a fricative lost in an 8 kHz recording's
  // narrow band leaves a faint gap above the room noise, a pause between phrases (200 ms is
  // 4.8 frames) falls to the room noise and closes the mouth. Then intervals shorter than
  // `min_speech_frames` are dropped (a click, a door). >= 0, >= 0, >= 0 dB, >= 1.
  int bridge_gap_frames = 3;
  int faint_gap_frames = 4;
  double pause_above_floor_db = 1.0;
  int min_speech_frames = 2;
  // MOUTH_FOLLOW: a frame asks for open when it is within `open_below_peak_db` of the speech's
  // loud level (the 90th percentile of its frames' loudness), closed when more than
  // `closed_below_peak_db` below it, else mid; a frame changes its drawing only when it
  // crosses a boundary by more than `hysteresis_db` / 2 (0 < open < closed, hysteresis >= 0).
  double open_below_peak_db = 6.0;
  double closed_below_peak_db = 15.0;
  double hysteresis_db = 3.0;
  // Voice, not sound: which loud stretches can be speech at all (core/voice_gate.h; on by
  // default, off for a singer). Used by the caller that computes the voice features.
  VoiceGateOptions gate;
  // DetectVoice with voice-like stretches: a speech interval's parts outside them of at most
  // this many frames, at its ends or between two stretches, are kept (a word's soft end that
  // loudness places better than the gate); longer ones are cut (the music a voice stops over).
  // >= 0.
  int keep_tail_frames = 4;
};

// INVALID_ARGUMENT naming the option ("stay_above_floor_db: 12 must be in (0,
// start_above_floor_db = 9]").
absl::Status ValidateVoiceOptions(const VoiceOptions& options);

struct VoiceActivity {
  double noise_floor_dbfs = kSilenceDbfs;   // estimated or given
  double start_dbfs = 0.0, stay_dbfs = 0.0;  // the two thresholds used
  double loud_dbfs = kSilenceDbfs;           // the speech's loud level (FOLLOW)
  std::vector<FrameInterval> speech;         // sorted, disjoint, in frames
  std::vector<MouthShape> follow;            // per frame: the drawing its loudness asks for
};

// The speech of per-frame loudness `dbfs` (FrameLoudness::Dbfs). With `voice_like`
// (core/voice_gate.h's stretches), the bridged intervals are cut to it and what is left
// shorter than min_speech_frames dropped: loudness finds where, the gate says whether it is a
// voice. Outside speech
// `follow` is closed; each speech interval starts from closed.
VoiceActivity DetectVoice(absl::Span<const double> dbfs, const VoiceOptions& options,
                          const std::vector<FrameInterval>* voice_like = nullptr);

// The percentile p (0 < p < 100) of `values`: the element of rank floor(p / 100 x (n - 1))
// in ascending order; kSilenceDbfs for none.
double Percentile(std::vector<double> values, double p);

}  // namespace koma

#endif  // KOMA_CORE_VOICE_ACTIVITY_H_

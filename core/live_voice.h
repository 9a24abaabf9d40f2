// LipBlink from a live voice (docs/semantics.md, "LipBlink from a live voice"; issue 44): the
// voice analysis of core/voice_activity.h and core/voice_gate.h run incrementally, one film-grid
// frame at a time, as audio blocks of any size arrive. Each grid frame is decided once, a fixed
// `lookahead_frames` after its end, and never revised: speech or pause, the mouth drawing (the
// offline drawing rules: holds of frames_per_shape from each speech interval's start, never the
// same drawing twice, closed in a pause) and the eyes' auto-blink.
//
// How it differs from the offline analysis of the whole recording:
// - the noise floor and the recording's range are percentiles of the last kLiveHistorySeconds
//   of grid frames (a histogram of 0.1 dB bins), not of the whole file;
// - a frame's speech is DetectVoice's answer on the last kLiveWindowFrames frames, ending at the
//   frame `lookahead_frames` after it: what happens later cannot bridge a gap for it, and the
//   speech gate sees kLiveProvisionalFrames voice-like frames past that end;
// - MOUTH_FOLLOW's loud level is the percentile of the speech frames decided so far (within
//   the history), and a hold follows the frames of it known at its first frame.
// The state is bounded: fixed-size rings and histograms, and the decided frames until popped.
// Deterministic, and independent of how the audio is cut into blocks: the loudness sums run
// sample by sample, the voice features are block-independent, and every decision is made at a
// grid-frame boundary from per-frame values.
#ifndef KOMA_CORE_LIVE_VOICE_H_
#define KOMA_CORE_LIVE_VOICE_H_

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "absl/status/status.h"
#include "absl/types/span.h"
#include "core/film_grid.h"
#include "core/grid_samples.h"
#include "core/lip_blink.h"
#include "core/split_mix64.h"
#include "core/voice_activity.h"
#include "core/voice_features.h"

namespace koma {

// Seconds of grid frames the running noise floor, range and loud level are percentiles of:
// long enough to hold the pauses of a talk (the offline 10th percentile is the room noise when
// a tenth of the take is pause), short enough to follow a room that changes.
inline constexpr double kLiveHistorySeconds = 60.0;
// Grid frames DetectVoice and the speech gate see for one decision (2 s at 24 fps): a stretch's
// rules reach 7 + 4 frames, a bridge 4; the rest is margin for a stretch's density.
inline constexpr int kLiveWindowFrames = 48;
inline constexpr int kMaxLookaheadFrames = 3;
// Voice-like frames assumed past the window's end for the speech gate (not for the loudness):
// a voice's stretch is kept from its 4th voice-like frame, so without them every onset would
// come up to 4 - lookahead frames late; 2 brings the onsets within a grid frame of the offline
// ones at lookahead 3 while music and noise open the mouth for under 1 % of their frames
// (docs/semantics.md, "LipBlink from a live voice", has the figures for 0 to 3).
inline constexpr int kLiveProvisionalFrames = 2;

struct LiveVoiceOptions {
  int sample_rate = 48000;                   // samples per second, 1 .. 1e6 (mono)
  double frame_fps = kDefaultTimingFps;      // the film grid's rate, (0, 1000]
  VoiceOptions voice;                        // as offline (noise_floor_dbfs given: used as is)
  // frames_per_shape, mode, mid_ratio, min (default 0), max (default max(1, min + 1)), as the
  // server's voice LipBlink; speech and detect_speech are not used (the voice gives speech).
  MouthOptions mouth;
  // mid_ratio, min (default 0), max (default 1), auto_blink (its keep is not used); fps is
  // frame_fps.
  EyeOptions eyes;
  int lookahead_frames = 2;                  // 0 .. kMaxLookaheadFrames grid frames
  uint64_t seed = 0;                         // RANDOM's coin and the auto-blink draws
};

// INVALID_ARGUMENT naming the option ("lookahead_frames: 5 must be in [0, 3]").
absl::Status ValidateLiveVoiceOptions(const LiveVoiceOptions& options);

struct LiveFrame {
  int64_t frame = 0;                          // grid frame, from 0 at the stream's first sample
  double time_s = 0.0;                        // its start: frame / frame_fps, seconds
  bool speech = false;
  MouthShape mouth = MouthShape::kClosed;
  double mouth_level = 0.0;                   // the level to write for `mouth`
  bool hold_start = false;                    // a mouth hold starts here (speech only)
  bool new_drawing = false;                   // the mouth's drawing differs from the last frame's
  MouthShape eye = MouthShape::kClosed;       // open, half (kMid) or closed
  double eye_level = 0.0;
  bool blink_start = false;                   // an auto-blink closes the eyes here
  // Samples past the frame's end the decision waited for (lookahead; at Finish, what there
  // was): the decision's latency at the audio's rate, before any transport.
  int64_t late_samples = 0;
  double dbfs = kSilenceDbfs;                 // the frame's loudness (for reports)
  double noise_floor_dbfs = kSilenceDbfs;     // the running floor the decision used
};

class LiveVoice {
 public:
  // `options` must pass ValidateLiveVoiceOptions.
  explicit LiveVoice(const LiveVoiceOptions& options);

  // Mono samples, full scale +-1, any block size (empty too).
  void Add(absl::Span<const float> mono);
  // The stream ends: the frames left (the last may be partial) are decided on what there is.
  // Add does nothing after it.
  void Finish();

  // The next decided frame in order, false when none is waiting. Decided frames wait here
  // until popped: pop after each Add to keep the state bounded.
  bool Pop(LiveFrame* frame);

  int64_t samples() const { return samples_; }
  // The running estimates the last decision used, dBFS.
  double noise_floor_dbfs() const { return floor_dbfs_; }
  double loud_dbfs() const { return loud_dbfs_; }

 private:
  // A sliding-window percentile of loudness on 0.1 dB bins from kSilenceDbfs to 0 dBFS, with
  // the counts of each kGroup bins too, so a percentile reads ~100 counts, not 1,502.
  class Histogram {
   public:
    static constexpr int kBins = 1502, kGroup = 32, kGroups = (kBins + kGroup - 1) / kGroup;
    static int Bin(double dbfs);
    void Add(int bin) { ++counts_[bin], ++groups_[bin / kGroup], ++total_; }
    void Remove(int bin) { --counts_[bin], --groups_[bin / kGroup], --total_; }
    // The bin of rank floor(p / 100 (n - 1)) in ascending order, as its value, dBFS;
    // kSilenceDbfs when empty.
    double Percentile(double p) const;

   private:
    std::array<int32_t, kBins> counts_{};
    std::array<int32_t, kGroups> groups_{};
    int32_t total_ = 0;
  };

  void CompleteFrame();
  void Decide(int64_t g, int64_t last, int64_t late_samples);
  bool SpeechAt(int64_t g, int64_t last);
  MouthShape FollowShape(double dbfs);
  void Mouth(bool speech, int64_t g, int64_t last, LiveFrame& out);
  void Eyes(int64_t g, LiveFrame& out);

  LiveVoiceOptions options_;
  GridSamples grid_;
  VoiceFeatures features_;
  std::vector<VoiceFrame> taken_;             // VoiceFeatures::TakeFrames's buffer
  double closed_ = 0.0, mid_ = 0.0, open_ = 0.0;            // mouth levels
  double eye_closed_ = 0.0, eye_half_ = 0.0, eye_open_ = 1.0;

  // Samples and the frame being summed.
  int64_t samples_ = 0;
  int64_t complete_ = 0;                      // grid frames whose samples are all in
  int64_t next_boundary_ = 0;                 // first sample of frame complete_ + 1
  double sum_ = 0.0;                          // sum of squares of frame complete_, in order
  int64_t count_ = 0;
  bool finished_ = false;

  // Per frame, rings indexed by frame mod their size.
  std::vector<double> dbfs_;                  // kLiveWindowFrames
  std::vector<VoiceFrame> voice_;             // kLiveWindowFrames
  std::vector<uint16_t> history_;             // the history's bins, bit 15: decided speech
  int history_size_ = 1;
  Histogram all_, speaking_;
  double floor_dbfs_ = kSilenceDbfs, loud_dbfs_ = kSilenceDbfs;
  // Scratch for one decision.
  std::vector<double> window_dbfs_;
  std::vector<VoiceFrame> window_voice_;

  // The mouth.
  int64_t decided_ = 0;                       // frames decided
  SplitMix64 mouth_rng_;
  bool in_speech_ = false;
  int hold_left_ = 0;                         // frames left in the current hold
  MouthShape shape_ = MouthShape::kClosed;    // the hold's drawing; closed in a pause
  MouthShape follow_ = MouthShape::kClosed;   // FOLLOW's Schmitt trigger state
  MouthShape shown_ = MouthShape::kClosed;    // the last frame's drawing
  // The eyes: the auto-blink walk of core/lip_blink_auto.cc, frame by frame.
  SplitMix64 blink_rng_;
  int64_t next_blink_ = 0;                    // the next blink's first frame
  int64_t blink_ = -1;                        // the last blink's first frame; -1: none yet

  std::deque<LiveFrame> ready_;
};

}  // namespace koma

#endif  // KOMA_CORE_LIVE_VOICE_H_

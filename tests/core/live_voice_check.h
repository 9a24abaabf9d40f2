// What the live voice analysis (core/live_voice.h) is checked against: the offline analysis of
// the whole recording (the server's voice LipBlink: FrameLoudness, VoiceFeatures, the speech
// gate, DetectVoice), the drawing rules frame by frame, and the boundaries of two speech
// tracks. Shared by live_voice_test and the live_voice_compare tool (tests/python's espeak-ng
// recordings).
#ifndef KOMA_TESTS_CORE_LIVE_VOICE_CHECK_H_
#define KOMA_TESTS_CORE_LIVE_VOICE_CHECK_H_

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/types/span.h"
#include "core/grid_samples.h"
#include "core/live_voice.h"
#include "core/voice_activity.h"
#include "core/voice_features.h"
#include "core/voice_gate.h"

namespace koma::testing {

// Per grid frame: speech in the offline analysis of the whole recording (one block: the
// server's decoder blocks change FrameLoudness's sums in their last bits only).
inline std::vector<bool> OfflineSpeech(absl::Span<const float> mono, int rate, double fps,
                                       const VoiceOptions& options) {
  FrameLoudness loudness(rate, fps);
  VoiceFeatures features(rate, fps);
  loudness.Add(mono);
  features.Add(mono);
  features.Finish();
  const int frames = loudness.frames_touched();
  const std::vector<FrameInterval> voice_like = VoiceLikeStretches(features, fps, options.gate);
  const VoiceActivity v = DetectVoice(loudness.Dbfs(frames), options, &voice_like);
  std::vector<bool> speech(static_cast<size_t>(frames), false);
  for (const FrameInterval& i : v.speech) {
    for (int f = i.begin; f < i.end; ++f) speech[f] = true;
  }
  return speech;
}

// The live analysis over `mono` in blocks of the given sizes (cycled), popped after each.
inline std::vector<LiveFrame> RunLive(absl::Span<const float> mono,
                                      const LiveVoiceOptions& options,
                                      const std::vector<size_t>& blocks) {
  LiveVoice live(options);
  std::vector<LiveFrame> out;
  LiveFrame f;
  size_t at = 0, b = 0;
  while (at < mono.size()) {
    const size_t n = std::min(mono.size() - at, blocks[b++ % blocks.size()]);
    live.Add(mono.subspan(at, n));
    at += n;
    while (live.Pop(&f)) out.push_back(f);
  }
  live.Finish();
  while (live.Pop(&f)) out.push_back(f);
  return out;
}

inline std::vector<FrameInterval> Runs(const std::vector<bool>& speech, int from) {
  std::vector<FrameInterval> runs;
  const int n = static_cast<int>(speech.size());
  for (int f = std::max(from, 0); f < n;) {
    if (!speech[f]) {
      ++f;
      continue;
    }
    const int begin = f;
    while (f < n && speech[f]) ++f;
    runs.push_back({begin, f});
  }
  return runs;
}

// The largest distance, in frames, between a boundary of `a` and the matching one of `b`
// from frame `from` on (tracks cut there), or -1 when their speech runs do not pair up (a run
// more or fewer).
inline int BoundaryError(const std::vector<bool>& a, const std::vector<bool>& b, int from) {
  const std::vector<FrameInterval> ra = Runs(a, from), rb = Runs(b, from);
  if (ra.size() != rb.size()) return -1;
  int worst = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    worst = std::max({worst, std::abs(ra[i].begin - rb[i].begin), std::abs(ra[i].end - rb[i].end)});
  }
  return worst;
}

// The first broken rule of a live track, "" when none: frames in order from 0; a pause shows
// the closed drawing; holds of frames_per_shape from each speech run's start (the last cut at
// its end), the first of a run mid or open, no hold the same drawing as the one before; the
// levels; new_drawing; the lateness (the lookahead's samples, at most that at the end); the
// auto-blink (closed `hold` frames, half `hold` frames, then open).
inline std::string CheckDrawingRules(const std::vector<LiveFrame>& frames,
                                     const LiveVoiceOptions& o, int64_t total_samples) {
  const GridSamples grid(o.sample_rate, o.frame_fps);
  const double closed = o.mouth.min.value_or(0.0);
  const double open = o.mouth.max.value_or(std::max(1.0, closed + 1.0));
  const double mid = closed + o.mouth.mid_ratio * (open - closed);
  const double eye_closed = o.eyes.min.value_or(0.0), eye_open = o.eyes.max.value_or(1.0);
  const double eye_half = eye_closed + o.eyes.mid_ratio * (eye_open - eye_closed);
  const int n = o.mouth.frames_per_shape;
  MouthShape previous_hold = MouthShape::kClosed, shown = MouthShape::kClosed;
  int in_hold = 0;  // frames of the current hold so far
  int64_t blink = -1;
  for (size_t i = 0; i < frames.size(); ++i) {
    const LiveFrame& f = frames[i];
    const std::string at = absl::StrCat("frame ", f.frame, ": ");
    if (f.frame != static_cast<int64_t>(i)) return absl::StrCat(at, "out of order at ", i);
    const bool starts_run = f.speech && (i == 0 || !frames[i - 1].speech);
    if (!f.speech) {
      if (f.mouth != MouthShape::kClosed) return absl::StrCat(at, "a pause not closed");
      if (f.hold_start) return absl::StrCat(at, "a hold starts in a pause");
      previous_hold = MouthShape::kClosed;
      in_hold = 0;
    } else {
      const bool due = starts_run || in_hold == n;
      if (f.hold_start != due) return absl::StrCat(at, "hold_start ", f.hold_start, ", due ", due);
      if (due) {
        if (f.mouth == previous_hold) return absl::StrCat(at, "a hold repeats its drawing");
        previous_hold = f.mouth;
        in_hold = 0;
      } else if (f.mouth != previous_hold) {
        return absl::StrCat(at, "the drawing changes inside a hold");
      }
      ++in_hold;
    }
    const double level = f.mouth == MouthShape::kClosed ? closed
                         : f.mouth == MouthShape::kMid  ? mid
                                                        : open;
    if (f.mouth_level != level) return absl::StrCat(at, "mouth level ", f.mouth_level);
    if (f.new_drawing != (f.mouth != shown)) return absl::StrCat(at, "new_drawing wrong");
    shown = f.mouth;
    const int64_t end = grid.FirstSample(f.frame + 1);
    const int64_t late = std::min(grid.FirstSample(f.frame + 1 + o.lookahead_frames),
                                  std::max(total_samples, end)) - end;
    if (f.late_samples != late) return absl::StrCat(at, "late ", f.late_samples, " not ", late);
    if (f.blink_start) {
      if (!o.eyes.auto_blink.enabled) return absl::StrCat(at, "a blink with auto-blink off");
      if (blink >= 0 && f.frame - blink < 2 * o.eyes.auto_blink.hold + 2) {
        return absl::StrCat(at, "a blink too soon after the last");
      }
      blink = f.frame;
    }
    const int64_t into = blink >= 0 ? f.frame - blink : INT64_MAX;
    const int hold = o.eyes.auto_blink.hold;
    const MouthShape eye = into < hold       ? MouthShape::kClosed
                           : into < 2 * hold ? MouthShape::kMid
                                             : MouthShape::kOpen;
    const double eye_level = eye == MouthShape::kClosed ? eye_closed
                             : eye == MouthShape::kMid  ? eye_half
                                                        : eye_open;
    if (f.eye != eye || f.eye_level != eye_level) return absl::StrCat(at, "eye wrong");
  }
  return "";
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_CORE_LIVE_VOICE_CHECK_H_

// Voice, not sound (docs/semantics.md): the stretches of a recording that sound like a speaking
// voice, from core/voice_features.h's per-frame voicing and spectral change, so loud music and
// noise stop opening the mouth. A frame is voice-like when it is voiced and its spectrum keeps
// changing (over its own step and the one before: a note's onset changes the spectrum once, a
// voice keeps doing so); voice-like frames close together form a stretch, kept when it holds
// enough of them, densely enough (a voice's syllables come every ~0.25 s; a melody's note
// changes and drum hits over a bass are sparser). DetectVoice keeps speech only inside the
// stretches, each widened over unvoiced frames for a word's unvoiced start or end (/s/, /k/).
#ifndef KOMA_CORE_VOICE_GATE_H_
#define KOMA_CORE_VOICE_GATE_H_

#include <vector>

#include "absl/status/status.h"
#include "absl/types/span.h"
#include "core/lip_blink.h"
#include "core/voice_features.h"

namespace koma {

struct VoiceGateOptions {
  // Off: every loud sound may be speech, as before issue 44 (a singer, a synthesised voice).
  bool enabled = true;
  // A voice-like frame: voicing >= `min_voicing` (0.25) and change >= `min_change` at it and at the
  // frame `step` earlier ([0, 1] each).
  double min_voicing = 0.25;
  double min_change = 0.1;
  // Voice-like frames at most `max_gap_s` apart join one stretch (a consonant, a closure, a
  // steady vowel: 7 grid frames at 24 fps); a stretch is kept with at least `min_frames_s` of voice-like frames
  // (4 grid frames) making at least `min_density` of it. Seconds, on the frame's grid rate.
  double max_gap_s = 7.0 / 24.0;
  double min_frames_s = 4.0 / 24.0;
  double min_density = 0.4;
  // Each kept stretch widened by up to this on each side (4 grid frames), seconds, but not
  // into a held sound (two voiced, steady frames): a word's unvoiced start or end (/s/, /k/),
  // not the music under it.
  double reach_s = 4.0 / 24.0;
};

// INVALID_ARGUMENT naming the option.
absl::Status ValidateVoiceGateOptions(const VoiceGateOptions& options);

// The voice-like stretches of `frames` (VoiceFeatures::frames(), `step` its step()) on a grid
// of `fps`, sorted and disjoint, within [0, frames.size()). Disabled: one stretch over all.
std::vector<FrameInterval> VoiceLikeStretches(absl::Span<const VoiceFrame> frames, int step,
                                              double fps, const VoiceGateOptions& options);

// The same from the extractor itself: every frame when its rate cannot show a pitch
// (VoiceFeatures::usable()).
std::vector<FrameInterval> VoiceLikeStretches(const VoiceFeatures& features, double fps,
                                              const VoiceGateOptions& options);

// The frames of `a` that are also in `b` (both sorted and disjoint).
std::vector<FrameInterval> Intersect(absl::Span<const FrameInterval> a,
                                     absl::Span<const FrameInterval> b);

}  // namespace koma

#endif  // KOMA_CORE_VOICE_GATE_H_

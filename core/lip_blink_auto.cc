// Auto-blink (beyond the paper, after CubismEyeBlink): blinks inserted at random intervals
// where the input does not blink, e.g. a motion whose eyes never move.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "core/lip_blink.h"
#include "core/lip_blink_internal.h"
#include "core/split_mix64.h"

namespace koma::lip_blink_internal {

// Frames from the end of one blink to the start of the next inserted one:
// round((mean + spread (2u - 1)) fps) with u = rng.Unit(), uniform in [0, 1). Clamped to
// at least 2 hold + 2, so the eye stays open longer than a blink takes (shorter would read
// as a flicker), and to at most frame_count + 1, which already ends past the clip, so the
// int64 positions of the walk cannot overflow. std::round is exact; no libm function with
// machine-dependent last bits is used.
int64_t DrawBlinkInterval(SplitMix64& rng, const AutoBlinkOptions& a, double fps,
                          int frame_count) {
  const double u = rng.Unit();
  const double seconds = a.mean_interval_s + a.spread_s * (2.0 * u - 1.0);  // > 0: spread < mean
  const double frames = std::round(seconds * fps);
  const double shortest = 2.0 * a.hold + 2.0;
  const double longest = static_cast<double>(frame_count) + 1.0;
  return static_cast<int64_t>(std::max(shortest, std::min(frames, longest)));
}

namespace {

Blink Inserted(int start, int hold) {
  Blink b;
  b.closing_begin = start;  // no closing phase: open snaps to closed
  b.closed_begin = start;
  b.closed_end = start + hold - 1;
  b.open_span = hold;  // the half-open frames
  b.hold = hold;
  b.automatic = true;
  return b;
}

}  // namespace

// The walk, in time order. A timer starts at frame 0 and fires after a drawn interval; the
// blink (closed `hold` frames, half-open `hold` frames) goes at the firing frame `start` when
// its guard window [start - 1, start + 2 hold] (one open frame either side) touches neither a
// detected blink's painted span nor a keep interval. Every blink, detected or inserted,
// restarts the timer at its end with a fresh draw: a detected blink that the window touches
// restarts it too, rather than being followed one frame later by an inserted blink (a double
// blink nobody asked for). A keep interval moves the blink just past it (start - 1 = its end)
// and the window is checked again. The walk stops once a blink would not fit in the clip.
std::vector<Blink> InsertAutoBlinks(std::vector<Blink> blinks, int frame_count,
                                    const EyeOptions& options, uint64_t seed) {
  const AutoBlinkOptions& a = options.auto_blink;
  if (!a.enabled) return blinks;
  const std::vector<int> ends = PaintEnds(blinks, frame_count);
  const std::vector<FrameInterval>& keep = a.keep;
  SplitMix64 rng(seed ^ kAutoBlinkStream);
  const int64_t span = 2 * a.hold;  // frames an inserted blink paints
  std::vector<Blink> inserted;
  size_t j = 0;  // the next detected blink
  size_t q = 0;  // the next keep interval
  int64_t start = DrawBlinkInterval(rng, a, options.fps, frame_count);
  while (start + span <= frame_count) {
    if (j < blinks.size() && blinks[j].closing_begin <= start + span) {  // before or touching
      start = ends[j] + DrawBlinkInterval(rng, a, options.fps, frame_count);
      ++j;
    } else if (q < keep.size() && keep[q].end < start) {  // wholly before start - 1
      ++q;
    } else if (q < keep.size() && keep[q].begin <= start + span) {  // touching
      start = keep[q].end + 1;
    } else {
      inserted.push_back(Inserted(static_cast<int>(start), a.hold));
      start += span + DrawBlinkInterval(rng, a, options.fps, frame_count);
    }
  }
  std::vector<Blink> all;
  all.reserve(blinks.size() + inserted.size());
  std::merge(blinks.begin(), blinks.end(), inserted.begin(), inserted.end(),
             std::back_inserter(all),
             [](const Blink& x, const Blink& y) { return x.closed_begin < y.closed_begin; });
  return all;
}

}  // namespace koma::lip_blink_internal

// ConvertMouth (docs/semantics.md, "LipBlink", paper section 3.2.1 and Fig. 5): speech intervals,
// holds of n frames inside them, and one of three shapes per hold, never the previous one.
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <vector>

#include "core/lip_blink.h"
#include "core/lip_blink_internal.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

// A frame pair (f - 1, f) "changes" when the curve moves by more than this fraction of its
// range: exact float equality would call rounding noise speech, a fixed absolute epsilon would
// depend on the parameter's units.
constexpr double kChangeFraction = 1e-6;

// The speech of `m` (whose max - min is `range`): both frames of every changing pair belong
// to it; intervals are the maximal runs of such frames, then gaps shorter than n frames are
// merged (a hold cannot show a pause that short anyway). A constant curve has no speech.
// One pass: runs arrive in time order, so each can be merged into the interval before it as
// it is found (touching runs have a gap of 0 < n). The per-frame test feeds a conditional
// move and a rarely taken branch, not a branch per frame: held mouth values change every
// few frames at random, which a branch would mispredict (~40 % of ConvertMouth's time).
std::vector<FrameInterval> DetectSpeech(absl::Span<const double> m, double range, int n) {
  std::vector<FrameInterval> speech;
  if (!(range > 0.0)) return speech;
  const double threshold = kChangeFraction * range;
  const int frame_count = static_cast<int>(m.size());
  int begin = -1;  // the interval being built: [begin, end); none while begin < 0
  int end = -1;
  for (int f = 1; f < frame_count; ++f) {
    const bool changes = std::fabs(m[f] - m[f - 1]) > threshold;
    // A new interval when the pair (f - 1, f) changes at least n frames after the last one.
    if (changes & ((begin < 0) | (f - 1 - end >= n))) {
      if (begin >= 0) speech.push_back({begin, end});
      begin = f - 1;
    }
    end = changes ? f + 1 : end;
  }
  if (begin >= 0) speech.push_back({begin, end});
  return speech;
}

// The two shapes allowed after `previous` (Fig. 5: never the same twice), more closed first.
std::array<MouthShape, 2> Allowed(MouthShape previous) {
  switch (previous) {
    case MouthShape::kClosed:
      return {MouthShape::kMid, MouthShape::kOpen};
    case MouthShape::kMid:
      return {MouthShape::kClosed, MouthShape::kOpen};
    case MouthShape::kOpen:
      break;
  }
  return {MouthShape::kClosed, MouthShape::kMid};
}

double Level(const MouthResult& r, MouthShape shape) {
  switch (shape) {
    case MouthShape::kClosed:
      return r.closed;
    case MouthShape::kMid:
      return r.mid;
    case MouthShape::kOpen:
      break;
  }
  return r.open;
}

// FOLLOW: the allowed shape whose level is nearest the mean of the input over the hold; a tie
// (or a NaN mean) goes to the more closed one.
MouthShape Follow(const MouthResult& r, MouthShape previous, absl::Span<const double> hold) {
  double sum = 0.0;
  for (double v : hold) sum += v;
  const double mean = sum / static_cast<double>(hold.size());
  const std::array<MouthShape, 2> allowed = Allowed(previous);
  const double d0 = std::fabs(Level(r, allowed[0]) - mean);
  const double d1 = std::fabs(Level(r, allowed[1]) - mean);
  return d1 < d0 ? allowed[1] : allowed[0];
}

// Holds of n frames from the interval's first frame, the last one cut at its end. The shape
// before the first hold counts as closed in every interval (the mouth rests between
// utterances), so each interval opens with mid or open.
void ConvertInterval(absl::Span<const double> input, const MouthOptions& options,
                     FrameInterval interval, SplitMix64& rng, MouthResult& result) {
  MouthShape previous = MouthShape::kClosed;
  for (int b = interval.begin; b < interval.end;) {
    const int length = std::min(options.frames_per_shape, interval.end - b);
    MouthShape shape;
    if (options.mode == MouthMode::kRandom) {
      // The top bit of one draw: index 0 (more closed) or 1, each with probability 1/2.
      shape = Allowed(previous)[rng.Next() >> 63];
    } else {
      shape = Follow(result, previous, input.subspan(b, length));
    }
    const double level = Level(result, shape);
    std::fill(result.values.begin() + b, result.values.begin() + b + length, level);
    result.holds.push_back({b, length, shape});
    previous = shape;
    b += length;  // not b += n: n may be near INT_MAX
  }
}

}  // namespace

namespace lip_blink_internal {

Extent BeginMouthResult(absl::Span<const double> input, const MouthOptions& options,
                        MouthResult* result) {
  result->values.assign(input.begin(), input.end());
  const Extent extent = ExtentOf(input);
  result->closed = options.min.value_or(extent.min);
  result->open = options.max.value_or(extent.max);
  result->mid = result->closed + options.mid_ratio * (result->open - result->closed);
  return extent;
}

}  // namespace lip_blink_internal

MouthResult ConvertMouth(absl::Span<const double> input, const MouthOptions& options,
                         uint64_t seed) {
  assert(ValidateMouthOptions(options, static_cast<int>(input.size())).ok());
  MouthResult result;
  const lip_blink_internal::Extent extent =
      lip_blink_internal::BeginMouthResult(input, options, &result);
  // Given intervals are used as they are (no merging): the caller knows the dialogue.
  result.speech = options.speech.empty() && options.detect_speech
                      ? DetectSpeech(input, extent.max - extent.min, options.frames_per_shape)
                      : options.speech;
  size_t hold_count = 0;  // ceil(length / n) per interval
  for (const FrameInterval& v : result.speech) {
    hold_count += static_cast<size_t>((v.end - v.begin - 1) / options.frames_per_shape) + 1;
  }
  result.holds.reserve(hold_count);
  // One generator for the whole clip, drawn in time order: one bit per RANDOM hold.
  SplitMix64 rng(seed);
  for (const FrameInterval& interval : result.speech) {
    ConvertInterval(input, options, interval, rng, result);
  }
  return result;
}

std::vector<MouthShape> MouthDrawings(const std::vector<MouthHold>& holds, int frame_count) {
  const int n = std::max(frame_count, 0);
  std::vector<MouthShape> drawings(static_cast<size_t>(n), MouthShape::kClosed);
  for (const MouthHold& hold : holds) {
    const int end = std::min(n, hold.begin + std::max(hold.length, 0));
    for (int f = std::max(hold.begin, 0); f < end; ++f) drawings[f] = hold.shape;
  }
  return drawings;
}

}  // namespace koma

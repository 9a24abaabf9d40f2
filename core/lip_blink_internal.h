// Pieces shared by the LipBlink sources (not part of the public API): interval validation,
// blink detection and painting spans, and the auto-blink walk.
#ifndef KOMA_CORE_LIP_BLINK_INTERNAL_H_
#define KOMA_CORE_LIP_BLINK_INTERNAL_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/types/span.h"
#include "core/lip_blink.h"
#include "core/split_mix64.h"

namespace koma::lip_blink_internal {

// Auto-blinks draw from SplitMix64(seed ^ kAutoBlinkStream), a stream of their own, so that
// turning them on does not change the mouth's draws (SplitMix64(seed)). "eyeblink" in ASCII.
inline constexpr uint64_t kAutoBlinkStream = 0x657965626c696e6bULL;

// An eye curve whose range (max - min) is below this counts as flat: its closed level then
// defaults to 0 (Live2D: 0 = eye shut) and it takes no part in linked detection (it carries
// no timing); levels spanning less than this detect no blinks (every frame would be both
// closed and open).
inline constexpr double kFlatRange = 1e-9;

// The smallest and largest value of `values` ({0, 0} when empty). Comparisons only, so exact;
// four independent accumulators instead of std::minmax_element, which branches on every
// value and mispredicts on noisy curves (over half of ConvertEyes' time before).
struct Extent {
  double min = 0.0;
  double max = 0.0;
};
Extent ExtentOf(absl::Span<const double> values);

// A mouth's answer begun: `input` copied into result->values and the closed, mid and open
// levels set (options' min and max, else the input's extent). Returns the input's extent.
Extent BeginMouthResult(absl::Span<const double> input, const MouthOptions& options,
                        MouthResult* result);

// Intervals sorted, disjoint, non-empty and within [0, frame_count]; messages name
// `path`[i] and the interval ("speech[2]: [40, 38) is empty or reversed").
absl::Status CheckIntervals(const std::vector<FrameInterval>& intervals, absl::string_view path,
                            int frame_count);

// An eye is held at a level when it stays open at that level (at or above level - delta
// (level - closed)) for this many frames: longer than any half-open drawing of a blink (k <= 3,
// paper Eq. 7), so a held level is where the eye settled, not a step of its opening.
inline constexpr int kHeldFrames = 4;

// The least value that counts as open at `level`: level - delta (level - closed), the paper's
// E_max - delta range with the level in place of E_max.
inline double OpenAtLeast(double level, double closed, double delta) {
  return level - delta * (level - closed);
}

// The maximal runs of frames at or below closed_at_most, in time order.
std::vector<FrameInterval> ClosedRuns(absl::Span<const double> signal, double closed_at_most);

// Per closed run (sorted, disjoint, non-empty): the open levels either side of it, read from
// the signal (docs/semantics.md, "LipBlink", "Open levels"): `before` the level the eye closes
// from, `after` the level it reopens to. `fixed` (E_max given) sets every level; `fallback` is
// used only when no frame lies outside the closed runs.
std::vector<BlinkLevels> OpenLevelsAround(absl::Span<const double> signal,
                                          const std::vector<FrameInterval>& runs, double closed,
                                          double delta, std::optional<double> fixed,
                                          double fallback);

// The blinks of `signal` (docs/semantics.md, "LipBlink"): closed frames are <= closed_at_most;
// one blink per maximal run of closed frames, in time order, with its closing phase (back to
// the last frame open at its `before` level), opening span (up to the first frame open at its
// `after` level) and hold k (paper Eq. 6-7). Levels as OpenLevelsAround; `closed` is E_min.
std::vector<Blink> DetectBlinks(absl::Span<const double> signal, double closed_at_most,
                                double closed, double delta, std::optional<double> fixed,
                                double fallback);

// Per blink (sorted, as DetectBlinks returns them): one past the last frame its repaint
// writes, clipped at the next blink's closing_begin and at frame_count.
std::vector<int> PaintEnds(const std::vector<Blink>& blinks, int frame_count);

// Frames from the end of one blink to the start of the next inserted one (see
// lip_blink_auto.cc), drawn from `rng`; also the live analysis's walk (core/live_voice.h).
int64_t DrawBlinkInterval(SplitMix64& rng, const AutoBlinkOptions& a, double fps,
                          int frame_count);

// `blinks` (sorted, detected) plus the auto-blinks options.auto_blink asks for, all sorted
// by frame; unchanged when auto-blink is disabled. See lip_blink_auto.cc for the walk.
std::vector<Blink> InsertAutoBlinks(std::vector<Blink> blinks, int frame_count,
                                    const EyeOptions& options, uint64_t seed);

}  // namespace koma::lip_blink_internal

#endif  // KOMA_CORE_LIP_BLINK_INTERNAL_H_

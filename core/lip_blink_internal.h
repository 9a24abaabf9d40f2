// Pieces shared by the LipBlink sources (not part of the public API): interval validation,
// blink detection and painting spans, and the auto-blink walk.
#ifndef KOMA_CORE_LIP_BLINK_INTERNAL_H_
#define KOMA_CORE_LIP_BLINK_INTERNAL_H_

#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "absl/types/span.h"
#include "core/lip_blink.h"

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

// Intervals sorted, disjoint, non-empty and within [0, frame_count]; messages name
// `path`[i] and the interval ("speech[2]: [40, 38) is empty or reversed").
absl::Status CheckIntervals(const std::vector<FrameInterval>& intervals, absl::string_view path,
                            int frame_count);

// The blinks of `signal` (docs/semantics.md, "LipBlink"): closed frames are <= closed_at_most, open
// frames >= open_at_least; one blink per maximal run of closed frames, in time order, with
// its closing phase, opening span and hold k (paper Eq. 6-7).
std::vector<Blink> DetectBlinks(absl::Span<const double> signal, double closed_at_most,
                                double open_at_least);

// Per blink (sorted, as DetectBlinks returns them): one past the last frame its repaint
// writes, clipped at the next blink's closing_begin and at frame_count.
std::vector<int> PaintEnds(const std::vector<Blink>& blinks, int frame_count);

// `blinks` (sorted, detected) plus the auto-blinks options.auto_blink asks for, all sorted
// by frame; unchanged when auto-blink is disabled. See lip_blink_auto.cc for the walk.
std::vector<Blink> InsertAutoBlinks(std::vector<Blink> blinks, int frame_count,
                                    const EyeOptions& options, uint64_t seed);

}  // namespace koma::lip_blink_internal

#endif  // KOMA_CORE_LIP_BLINK_INTERNAL_H_

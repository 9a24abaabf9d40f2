// RetimeSkeletal on real takes (docs/semantics.md, "Cuts and shots", "Omission rate",
// "Drawing rate"): an isolated jump in the pose (a T-pose calibration frame, the join of two
// shots, a glitch frame) is a cut, and the clip is retimed as separate shots on either side,
// each as if it were alone, with its share of the omissions and holds by length.
#ifndef KOMA_CORE_RETIME_SHOTS_H_
#define KOMA_CORE_RETIME_SHOTS_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/types/span.h"
#include "core/distance.h"
#include "core/film_grid.h"
#include "core/retime.h"

namespace koma {

// The cut rule. SSD(k) = dist(k - 1, k) between source frames (squared length units, the
// distance of core/distance.h). A *jump* is a pair with SSD(k) > median_ratio * m, m the median
// SSD of the clip's pairs (the lower middle value when their count is even). A maximal run of
// consecutive jumps of at most kMaxCutPairs pairs is *isolated* when its smallest SSD is at
// least neighbour_ratio times the larger SSD of the pairs just outside it (the one that exists
// at an end of the clip; a run with no pair outside it is not isolated). Every pair of an
// isolated run is a cut. neighbour_ratio 0 turns cuts off.
inline constexpr double kDefaultCutNeighbourRatio = 20.0;
inline constexpr double kDefaultCutMedianRatio = 20.0;
// One pair: a jump between two shots or after a calibration frame; two: a glitch frame (the
// jump into it and the jump out).
inline constexpr int kMaxCutPairs = 2;

struct CutRule {
  double neighbour_ratio = kDefaultCutNeighbourRatio;  // 0 (off) or >= 1
  double median_ratio = kDefaultCutMedianRatio;        // >= 0
};

// INVALID_ARGUMENT naming the request fields cut_neighbour_ratio / cut_median_ratio.
absl::Status ValidateCutRule(const CutRule& rule);

// The cuts of a clip whose per-frame SSD is `ssd` (ssd[0] unused, ssd[k] = dist(k - 1, k)):
// the first frame of each shot after a cut (the k of each cut pair), ascending. Empty when
// rule.neighbour_ratio is 0 or the clip has fewer than 3 frames.
std::vector<int32_t> FindCuts(absl::Span<const double> ssd, const CutRule& rule);

// `total` split over shots of the given lengths in proportion to length, by largest
// remainder (Hamilton): each gets floor(total * length / sum), and what is left goes one each
// to the largest remainders, ties to the earlier shot. Lengths 0 get nothing. Exact integers.
std::vector<int> SplitByLength(int total, const std::vector<int>& lengths);

// Shots of fewer than this many frames pass through unchanged: their only frames are the
// first and the last, which the algorithm keeps as key poses.
inline constexpr int kMinRetimedShotFrames = 3;

// How the whole clip's settings become each shot's.
struct ShotBudget {
  // omissions and holds: the whole clip's totals; max_hold, keep_length, order as they are.
  RetimeOptions totals;
  // > 0: each shot's max_drawings = CeilOfRate(its frames * drawings_per_frame) (a drawing
  // rate in drawings per counted frame); 0: none.
  double drawings_per_frame = 0.0;
  // Hold steps per shot: kHoldStepsPerFrameAndHold * its frames * max_hold (a bound, with a
  // drawing rate and no hold count) instead of its share of totals.holds.
  bool holds_per_frame_cap = false;
};

// Each shot's RetimeOptions, shots given by their lengths in counted frames. Shots of at
// least kMinRetimedShotFrames frames share totals.omissions and totals.holds by
// SplitByLength (a shot's omissions at most its frames - 3); shorter shots get none. With a
// single shot the totals are its own, unchanged.
std::vector<RetimeOptions> ShotOptions(const ShotBudget& budget, const std::vector<int>& lengths);

// ceil(x), but an x within 1e-4 (relative) above a whole number counts as that number, as the
// film grid's rates do: 1 / 0.008333 s is 120.005 fps, and 8 drawings a second of it are holds
// of 15 frames, not 16.
int CeilOfRate(double x);

// Hold steps a drawing rate may take when no hold count is given: this many times the frames
// times max_hold. A hold step can slide a run along without removing a drawing; the real clips
// and samples reach their target within 1.3 times frames x max_hold (the pitch on threes: 491
// steps for 130 frames), and the bound keeps an adversarial clip's steps linear.
inline constexpr int kHoldStepsPerFrameAndHold = 4;

// Omissions for a rate: floor(per_second * frames / frames_per_second + 1/2), at most
// max(0, frames - 3) (docs/semantics.md, "Omission rate").
int OmissionsForRate(double per_second, int frames, double frames_per_second);

// The per-frame SSD of the source clip (as FrameDistance::InputSsd over all its frames, bit
// for bit), computed over chunks so that a transform (root_relative, camera) never copies more
// than a chunk. `positions` is frame_count x joints x 3, frame-major.
absl::StatusOr<std::vector<double>> SourceSsd(absl::Span<const double> positions,
                                              int frame_count, int joints,
                                              const DistanceOptions& options);

// A clip retimed shot by shot.
struct ShotsRetimed {
  TimingMap map;                      // output frames; source frames of the whole clip
  std::vector<double> input_ssd;      // per counted frame (grid frames of the shots' grids)
  std::vector<int32_t> grid_frames;   // with a grid: per output frame, its retimed grid frame
  std::vector<int32_t> grid_samples;  // with a grid: per grid frame, its source frame
};

// Retimes source frames [starts[i], starts[i + 1]) (the last to frame_count) as shot i with
// options[i], each as if it were a clip of its own: on its own film grid (starting at its
// first frame) when `grid` is set, written back at the source rate or (at_source_rate false)
// one frame per grid frame, and concatenates the results: source frames, deleted and hidden
// frames offset by the shot's first frame, grid frames by the grid frames before it, counts
// summed. input_ssd[first counted frame of shot i > 0] is the distance from the previous
// shot's last counted frame (the jump itself). Shots too short to retime (fewer than
// kMinRetimedShotFrames counted frames) pass through unchanged. starts[0] must be 0.
absl::StatusOr<ShotsRetimed> RetimeShots(absl::Span<const double> positions, int frame_count,
                                         int joints, const DistanceOptions& distance_options,
                                         const std::optional<FilmGrid>& grid, bool at_source_rate,
                                         const std::vector<int32_t>& starts,
                                         const std::vector<RetimeOptions>& options);

}  // namespace koma

#endif  // KOMA_CORE_RETIME_SHOTS_H_

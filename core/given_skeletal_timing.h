// A RetimeSkeletal timing given by the caller instead of chosen by the algorithm
// (docs/semantics.md, "A given timing"): per counted frame (grid frame on a film grid, else
// output frame) the source frame it shows. Expanded to output frames exactly as a chosen
// timing is (ExpandGridTiming), so the motion is the one koma writes for that timing.
#ifndef KOMA_CORE_GIVEN_SKELETAL_TIMING_H_
#define KOMA_CORE_GIVEN_SKELETAL_TIMING_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "core/film_grid.h"
#include "core/retime.h"

namespace koma {

// INVALID_ARGUMENT naming `field` and the value: 1 <= length <= counted_frames (the clip's
// grid frames on a grid, else frame_count), each entry within [0, frame_count - 1]
// ("given_timing.source_frames[17]: 812 is past the clip's last frame 799").
absl::Status ValidateGivenSkeletalTiming(const std::vector<int32_t>& source_frames,
                                         int frame_count, int counted_frames,
                                         absl::string_view field);

struct GivenSkeletalRetimed {
  // Output frames: source_frames and kinds (kOriginal where the given timing starts a drawing,
  // kHeld where it repeats the counted frame before); deleted: the source frames (the grid's
  // samples on a grid) the given timing shows nowhere, ascending; hidden and every count empty.
  TimingMap map;
  std::vector<int32_t> grid_frames;   // on a grid: per output frame, its given counted frame
  std::vector<int32_t> grid_samples;  // on a grid: per grid frame, its sampled source frame
  int longest_hold = 0;               // counted frames
};

// Requires ValidateGivenSkeletalTiming OK. at_source_rate (with a grid): output frame k shows
// the given entry of the grid frame its time falls in, for k below min(frame_count, the first
// source frame at or after the given timing's end); otherwise one output frame per entry.
GivenSkeletalRetimed ApplyGivenSkeletalTiming(const std::vector<int32_t>& source_frames,
                                              const std::optional<FilmGrid>& grid,
                                              int frame_count, bool at_source_rate);

}  // namespace koma

#endif  // KOMA_CORE_GIVEN_SKELETAL_TIMING_H_

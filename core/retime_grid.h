// RetimeSkeletal on the film grid (docs/semantics.md, "The film grid"): the source is sampled
// on the grid, the Kitamura algorithm runs on that sequence unchanged, and the result is
// written back at the source rate (or at the grid rate on request).
#ifndef KOMA_CORE_RETIME_GRID_H_
#define KOMA_CORE_RETIME_GRID_H_

#include <cstdint>
#include <vector>

#include "core/film_grid.h"
#include "core/retime.h"

namespace koma {

// Per grid frame g of a clip of `source_frames` frames: the source frame nearest its time,
// ties to the earlier (non-decreasing; a verbatim frame, never an interpolation).
std::vector<int32_t> GridSamples(const FilmGrid& grid, int source_frames);

struct GridRetimed {
  // The timing map in output frames: source_frames index the *source* clip; kinds, counts
  // as the grid run gave them; deleted / hidden are source frames the grid showed and the
  // output no longer shows.
  TimingMap map;
  // Per output frame: the frame of the retimed grid sequence it shows.
  std::vector<int32_t> grid_frames;
};

// `grid_map` is a TimingMap over the grid sequence (source_frames index `samples`).
// at_source_rate: output frame k (at the source rate) shows the grid drawing its time falls
// in, GridFrameOf(k), for k below min(source_frames, the first source frame at or after the
// grid sequence's end): with keep_length that is exactly source_frames. Otherwise one output
// frame per grid frame.
GridRetimed ExpandGridTiming(const TimingMap& grid_map, const std::vector<int32_t>& samples,
                             const FilmGrid& grid, int source_frames, bool at_source_rate);

}  // namespace koma

#endif  // KOMA_CORE_RETIME_GRID_H_

#include "core/retime_grid.h"

#include <algorithm>

namespace koma {
namespace {

// The sampled source frames of `grid_gone` (grid indices) that no output frame shows,
// ascending and unique, skipping those already in `taken`.
std::vector<int32_t> GoneSourceFrames(const std::vector<int32_t>& grid_gone,
                                      const std::vector<int32_t>& samples,
                                      const std::vector<bool>& shown,
                                      const std::vector<int32_t>& taken) {
  std::vector<int32_t> gone;
  for (int32_t g : grid_gone) {
    const int32_t source = samples[static_cast<size_t>(g)];
    if (shown[static_cast<size_t>(source)]) continue;
    if (std::binary_search(taken.begin(), taken.end(), source)) continue;
    gone.push_back(source);
  }
  std::sort(gone.begin(), gone.end());
  gone.erase(std::unique(gone.begin(), gone.end()), gone.end());
  return gone;
}

}  // namespace

std::vector<int32_t> GridSamples(const FilmGrid& grid, int source_frames) {
  const int count = grid.GridFrameCount(source_frames);
  std::vector<int32_t> samples(static_cast<size_t>(count));
  for (int g = 0; g < count; ++g) samples[g] = grid.NearestSourceFrame(g, source_frames - 1);
  return samples;
}

GridRetimed ExpandGridTiming(const TimingMap& grid_map, const std::vector<int32_t>& samples,
                             const FilmGrid& grid, int source_frames, bool at_source_rate) {
  GridRetimed out;
  TimingMap& map = out.map;
  const int grid_length = static_cast<int>(grid_map.source_frames.size());
  const int length = at_source_rate
                         ? std::min(source_frames, grid.FirstSourceFrameAtOrAfter(grid_length))
                         : grid_length;
  map.source_frames.resize(static_cast<size_t>(length));
  map.kinds.resize(static_cast<size_t>(length));
  out.grid_frames.resize(static_cast<size_t>(length));
  std::vector<bool> shown(static_cast<size_t>(source_frames), false);
  for (int k = 0; k < length; ++k) {
    const int t = at_source_rate ? std::min(grid.GridFrameOf(k), grid_length - 1) : k;
    const int32_t source = samples[static_cast<size_t>(grid_map.source_frames[t])];
    map.source_frames[k] = source;
    map.kinds[k] = grid_map.kinds[t];
    out.grid_frames[k] = t;
    shown[static_cast<size_t>(source)] = true;
  }
  map.deleted = GoneSourceFrames(grid_map.deleted, samples, shown, {});
  map.hidden = GoneSourceFrames(grid_map.hidden, samples, shown, map.deleted);
  map.omissions_applied = grid_map.omissions_applied;
  map.duplicates_applied = grid_map.duplicates_applied;
  map.duplicates_skipped = grid_map.duplicates_skipped;
  map.holds_applied = grid_map.holds_applied;
  map.duplicates_omitted = grid_map.duplicates_omitted;
  map.duplicates_held = grid_map.duplicates_held;
  return out;
}

}  // namespace koma

#include "core/given_skeletal_timing.h"

#include <algorithm>
#include <numeric>

#include "absl/strings/str_cat.h"
#include "core/retime_grid.h"

namespace koma {

absl::Status ValidateGivenSkeletalTiming(const std::vector<int32_t>& source_frames,
                                         int frame_count, int counted_frames,
                                         absl::string_view field) {
  const int length = static_cast<int>(source_frames.size());
  if (length < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": empty; give the source frame of at least one frame"));
  }
  if (length > counted_frames) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": ", length, " frames is longer than the clip's ", counted_frames,
                     counted_frames == frame_count ? " frames" : " grid frames"));
  }
  for (int t = 0; t < length; ++t) {
    const int32_t s = source_frames[static_cast<size_t>(t)];
    if (s < 0) {
      return absl::InvalidArgumentError(absl::StrCat(field, "[", t, "]: ", s, " must be >= 0"));
    }
    if (s >= frame_count) {
      return absl::InvalidArgumentError(absl::StrCat(field, "[", t, "]: ", s,
                                                     " is past the clip's last frame ",
                                                     frame_count - 1));
    }
  }
  return absl::OkStatus();
}

namespace {

// The counted frames' map: kinds from runs, deleted = `candidates` not shown, counts 0.
TimingMap CountedMap(const std::vector<int32_t>& source_frames,
                     const std::vector<int32_t>& candidates, int frame_count, int* longest) {
  TimingMap map;
  map.source_frames = source_frames;
  map.kinds.resize(source_frames.size());
  std::vector<bool> shown(static_cast<size_t>(frame_count), false);
  int run = 0;
  *longest = 0;
  for (size_t t = 0; t < source_frames.size(); ++t) {
    const bool held = t > 0 && source_frames[t] == source_frames[t - 1];
    map.kinds[t] = held ? FrameKind::kHeld : FrameKind::kOriginal;
    run = held ? run + 1 : 1;
    *longest = std::max(*longest, run);
    shown[static_cast<size_t>(source_frames[t])] = true;
  }
  for (int32_t s : candidates) {
    if (!shown[static_cast<size_t>(s)] &&
        (map.deleted.empty() || map.deleted.back() != s)) {  // candidates are non-decreasing
      map.deleted.push_back(s);
    }
  }
  return map;
}

}  // namespace

GivenSkeletalRetimed ApplyGivenSkeletalTiming(const std::vector<int32_t>& source_frames,
                                              const std::optional<FilmGrid>& grid,
                                              int frame_count, bool at_source_rate) {
  GivenSkeletalRetimed out;
  if (!grid) {
    std::vector<int32_t> all(static_cast<size_t>(frame_count));
    std::iota(all.begin(), all.end(), 0);
    out.map = CountedMap(source_frames, all, frame_count, &out.longest_hold);
    return out;
  }
  out.grid_samples = GridSamples(*grid, frame_count);
  const TimingMap counted =
      CountedMap(source_frames, out.grid_samples, frame_count, &out.longest_hold);
  // ExpandGridTiming reads the counted map's entries through `samples`; here they are source
  // frames already, so the samples are the identity.
  std::vector<int32_t> identity(static_cast<size_t>(frame_count));
  std::iota(identity.begin(), identity.end(), 0);
  TimingMap indexed = counted;
  indexed.deleted.clear();  // reported from the counted map, not re-derived from output frames
  GridRetimed expanded = ExpandGridTiming(indexed, identity, *grid, frame_count, at_source_rate);
  out.map = std::move(expanded.map);
  out.map.deleted = counted.deleted;
  out.grid_frames = std::move(expanded.grid_frames);
  return out;
}

}  // namespace koma

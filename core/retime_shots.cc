#include "core/retime_shots.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "absl/strings/str_cat.h"
#include "core/retime_grid.h"

namespace koma {
namespace {

// Frames per chunk of SourceSsd: a chunk of a 60-joint clip is 5.6 MB of positions.
constexpr int kSsdChunkFrames = 4096;

// The timing map that shows every frame of an n-frame clip as it is.
TimingMap IdentityMap(int n) {
  TimingMap map;
  map.source_frames.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) map.source_frames[static_cast<size_t>(k)] = k;
  map.kinds.assign(static_cast<size_t>(n), FrameKind::kOriginal);
  return map;
}

// Positions of `frames` (frame indices into `positions`), copied in order.
std::vector<double> GatherFrames(absl::Span<const double> positions, int per_frame,
                                 absl::Span<const int32_t> frames) {
  std::vector<double> out(frames.size() * static_cast<size_t>(per_frame));
  double* dst = out.data();
  for (int32_t frame : frames) {
    std::memcpy(dst, positions.data() + static_cast<size_t>(frame) * per_frame,
                sizeof(double) * per_frame);
    dst += per_frame;
  }
  return out;
}

void AppendOffset(const std::vector<int32_t>& from, int32_t offset, std::vector<int32_t>& to) {
  for (int32_t v : from) to.push_back(v + offset);
}

}  // namespace

absl::Status ValidateCutRule(const CutRule& rule) {
  if (!std::isfinite(rule.neighbour_ratio) ||
      (rule.neighbour_ratio != 0.0 && rule.neighbour_ratio < 1.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("cut_neighbour_ratio: ", rule.neighbour_ratio,
                     " must be 0 (no cuts) or a finite ratio >= 1"));
  }
  if (!std::isfinite(rule.median_ratio) || rule.median_ratio < 0.0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "cut_median_ratio: ", rule.median_ratio, " must be a finite ratio >= 0"));
  }
  return absl::OkStatus();
}

std::vector<int32_t> FindCuts(absl::Span<const double> ssd, const CutRule& rule) {
  std::vector<int32_t> cuts;
  const int n = static_cast<int>(ssd.size());
  if (rule.neighbour_ratio == 0.0 || n < 3) return cuts;
  // The median of the n - 1 pairs 1 .. n-1, the lower middle value for an even count.
  std::vector<double> sorted(ssd.begin() + 1, ssd.end());
  const size_t middle = (sorted.size() - 1) / 2;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(middle), sorted.end());
  const double threshold = rule.median_ratio * sorted[middle];
  int k = 1;
  while (k < n) {
    if (!(ssd[k] > threshold)) {
      ++k;
      continue;
    }
    // A maximal run of jumps k .. last.
    int last = k;
    while (last + 1 < n && ssd[last + 1] > threshold) ++last;
    const bool has_before = k > 1;
    const bool has_after = last + 1 < n;
    if (last - k + 1 <= kMaxCutPairs && (has_before || has_after)) {
      double outside = 0.0;
      if (has_before) outside = ssd[k - 1];
      if (has_after) outside = std::max(outside, ssd[last + 1]);
      double smallest = ssd[k];
      for (int j = k + 1; j <= last; ++j) smallest = std::min(smallest, ssd[j]);
      if (smallest >= rule.neighbour_ratio * outside) {
        for (int j = k; j <= last; ++j) cuts.push_back(j);
      }
    }
    k = last + 1;
  }
  return cuts;
}

std::vector<int> SplitByLength(int total, const std::vector<int>& lengths) {
  std::vector<int> shares(lengths.size(), 0);
  int64_t sum = 0;
  for (int length : lengths) sum += std::max(length, 0);
  if (sum == 0 || total <= 0) return shares;
  std::vector<int64_t> remainders(lengths.size(), -1);
  int64_t given = 0;
  for (size_t i = 0; i < lengths.size(); ++i) {
    if (lengths[i] <= 0) continue;
    const int64_t product = static_cast<int64_t>(total) * lengths[i];
    shares[i] = static_cast<int>(product / sum);
    remainders[i] = product % sum;
    given += shares[i];
  }
  for (int64_t left = total - given; left > 0; --left) {
    size_t best = 0;
    for (size_t i = 1; i < lengths.size(); ++i) {
      if (remainders[i] > remainders[best]) best = i;  // strict: ties to the earlier shot
    }
    ++shares[best];
    remainders[best] = -1;
  }
  return shares;
}

std::vector<RetimeOptions> ShotOptions(const ShotBudget& budget, const std::vector<int>& lengths) {
  std::vector<int> retimed(lengths.size(), 0);
  for (size_t i = 0; i < lengths.size(); ++i) {
    if (lengths[i] >= kMinRetimedShotFrames) retimed[i] = lengths[i];
  }
  const bool single = lengths.size() == 1;
  const std::vector<int> omissions = SplitByLength(budget.totals.omissions, retimed);
  const std::vector<int> holds = SplitByLength(budget.totals.holds, retimed);
  std::vector<RetimeOptions> options(lengths.size(), budget.totals);
  for (size_t i = 0; i < lengths.size(); ++i) {
    RetimeOptions& shot = options[i];
    const int64_t frames = lengths[i];
    if (!single) {
      shot.omissions = std::min(omissions[i], std::max(0, lengths[i] - 3));
      shot.holds = holds[i];
    }
    if (budget.holds_per_frame_cap) {
      shot.holds = static_cast<int>(std::min<int64_t>(
          kHoldStepsPerFrameAndHold * frames * budget.totals.max_hold, INT32_MAX));
    }
    if (budget.drawings_per_frame > 0.0) {
      shot.max_drawings =
          std::max(1, CeilOfRate(static_cast<double>(frames) * budget.drawings_per_frame));
    }
    if (lengths[i] < kMinRetimedShotFrames && !single) {
      shot.omissions = 0;
      shot.holds = 0;
    }
  }
  return options;
}

int CeilOfRate(double x) {
  const double whole = std::ceil(x * (1.0 - 1e-4));
  return whole >= 2147483647.0 ? INT32_MAX : static_cast<int>(whole);
}

int OmissionsForRate(double per_second, int frames, double frames_per_second) {
  const double wanted = std::floor(per_second * frames / frames_per_second + 0.5);
  const int most = std::max(0, frames - 3);
  if (!(wanted > 0.0)) return 0;
  return wanted >= most ? most : static_cast<int>(wanted);
}

absl::StatusOr<std::vector<double>> SourceSsd(absl::Span<const double> positions,
                                              int frame_count, int joints,
                                              const DistanceOptions& options) {
  std::vector<double> ssd(static_cast<size_t>(std::max(frame_count, 0)), 0.0);
  const size_t per_frame = 3 * static_cast<size_t>(joints);
  // Chunk c covers frames first .. first + count - 1 and overlaps the previous one by a frame,
  // so every pair lies in one chunk.
  for (int first = 0; first + 1 < frame_count; first += kSsdChunkFrames) {
    const int count = std::min(kSsdChunkFrames + 1, frame_count - first);
    absl::StatusOr<FrameDistance> chunk = FrameDistance::CreateView(
        positions.subspan(static_cast<size_t>(first) * per_frame, count * per_frame), count,
        joints, options);
    if (!chunk.ok()) return chunk.status();
    for (int k = 1; k < count; ++k) ssd[static_cast<size_t>(first + k)] = (*chunk)(k - 1, k);
  }
  return ssd;
}

absl::StatusOr<ShotsRetimed> RetimeShots(absl::Span<const double> positions, int frame_count,
                                         int joints, const DistanceOptions& distance_options,
                                         const std::optional<FilmGrid>& grid, bool at_source_rate,
                                         const std::vector<int32_t>& starts,
                                         const std::vector<RetimeOptions>& options) {
  ShotsRetimed out;
  TimingMap& map = out.map;
  const int per_frame = 3 * joints;
  int32_t retimed_offset = 0;  // frames of the retimed grid sequences before (grid_frames)
  int32_t previous_last = -1;  // the previous shot's last counted source frame
  for (size_t i = 0; i < starts.size(); ++i) {
    const int32_t first = starts[i];
    const int n = (i + 1 < starts.size() ? starts[i + 1] : frame_count) - first;
    // The shot's counted frames (its grid samples, or all its frames) as source frames of the
    // shot, and their positions.
    std::vector<int32_t> samples;
    if (grid) {
      samples = GridSamples(*grid, n);
    } else {
      samples.resize(static_cast<size_t>(n));
      for (int k = 0; k < n; ++k) samples[static_cast<size_t>(k)] = k;
    }
    const int counted = static_cast<int>(samples.size());
    std::vector<int32_t> global(samples);
    for (int32_t& s : global) s += first;
    // On a grid the shot's samples are copied (as the server's grid path does); without one
    // its frames are read in place.
    const std::vector<double> shot_positions =
        grid ? GatherFrames(positions, per_frame, global) : std::vector<double>();
    const absl::Span<const double> shot_view =
        grid ? absl::MakeConstSpan(shot_positions)
             : positions.subspan(static_cast<size_t>(first) * per_frame,
                                 static_cast<size_t>(n) * per_frame);
    absl::StatusOr<FrameDistance> distance =
        FrameDistance::CreateView(shot_view, counted, joints, distance_options);
    if (!distance.ok()) return distance.status();
    TimingMap shot_map;
    std::vector<double> ssd;
    if (counted >= kMinRetimedShotFrames &&
        ValidateRetimeOptions(options[i], counted).ok()) {
      shot_map = RetimeFast(*distance, options[i], &ssd);
    } else {
      shot_map = IdentityMap(counted);
      ssd = distance->InputSsd();
    }
    if (previous_last >= 0) {
      // The jump: from the previous shot's last counted frame to this shot's first.
      const int32_t pair[2] = {previous_last, first};
      const std::vector<double> two = GatherFrames(positions, per_frame, pair);
      absl::StatusOr<FrameDistance> jump =
          FrameDistance::CreateView(two, 2, joints, distance_options);
      if (!jump.ok()) return jump.status();
      ssd[0] = (*jump)(0, 1);
    }
    previous_last = global.back();
    out.input_ssd.insert(out.input_ssd.end(), ssd.begin(), ssd.end());
    // The retimed grid sequence of this shot is its timing map before expansion.
    const int32_t retimed_length = static_cast<int32_t>(shot_map.source_frames.size());
    TimingMap expanded;
    std::vector<int32_t> grid_frames;
    if (grid) {
      GridRetimed g = ExpandGridTiming(shot_map, samples, *grid, n, at_source_rate);
      expanded = std::move(g.map);
      grid_frames = std::move(g.grid_frames);
      AppendOffset(global, 0, out.grid_samples);
      AppendOffset(grid_frames, retimed_offset, out.grid_frames);
    } else {
      expanded = std::move(shot_map);
    }
    AppendOffset(expanded.source_frames, first, map.source_frames);
    map.kinds.insert(map.kinds.end(), expanded.kinds.begin(), expanded.kinds.end());
    AppendOffset(expanded.deleted, first, map.deleted);
    AppendOffset(expanded.hidden, first, map.hidden);
    map.omissions_applied += expanded.omissions_applied;
    map.duplicates_applied += expanded.duplicates_applied;
    map.duplicates_skipped += expanded.duplicates_skipped;
    map.holds_applied += expanded.holds_applied;
    map.duplicates_omitted += expanded.duplicates_omitted;
    map.duplicates_held += expanded.duplicates_held;
    retimed_offset += retimed_length;
  }
  return out;
}

}  // namespace koma

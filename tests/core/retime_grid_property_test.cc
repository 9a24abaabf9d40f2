// RetimeSkeletal on the film grid (docs/semantics.md, "The film grid"), on 500 random clips at each
// source rate 24 .. 240 fps and 29.97 (and, for the first property, 10, 12, 15 and 23.976):
//  - retiming through the grid (GridSamples, RetimeFast on the gathered frames,
//    ExpandGridTiming) equals retiming the clip's grid-sampled 24 fps version with RetimeNaive
//    and expanding that map back to the source rate by "source frame k shows the drawing of
//    grid frame floor(k * 24 / R)"; the sampling and the expansion are written here from the
//    rules with exact integer arithmetic on the true rate, not with FilmGrid;
//  - with default options no drawing is shown for less than a grid frame (but at the clip's
//    end) nor, held, for more than max_hold grid frames, in seconds within one source frame.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/distance.h"
#include "core/film_grid.h"
#include "core/retime.h"
#include "core/retime_grid.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

constexpr int kClipsPerRate = 500;

// A source rate as the exact fraction num / den frames per second.
struct Rate {
  int64_t num;
  int64_t den;
  double fps() const { return static_cast<double>(num) / static_cast<double>(den); }
  friend void PrintTo(const Rate& r, std::ostream* os) { *os << r.num << "/" << r.den << " fps"; }
};

const Rate kRates[] = {{24, 1},  {25, 1},  {30, 1},  {50, 1},    {60, 1},
                       {100, 1}, {120, 1}, {240, 1}, {2997, 100}};

// Grid frames g (at g / 24 s) at or before the last source frame's time (n - 1) / R.
int RefGridCount(Rate r, int n) {
  return static_cast<int>((static_cast<int64_t>(n - 1) * 24 * r.den) / r.num) + 1;
}

// Per grid frame: the source frame nearest g / 24 s, ties to the earlier.
std::vector<int32_t> RefSamples(Rate r, int n) {
  std::vector<int32_t> samples;
  for (int64_t g = 0; g < RefGridCount(r, n); ++g) {
    // Source time g * R / 24 frames = g * num / (24 den): k below it, k + 1 above it.
    const int64_t k = (g * r.num) / (24 * r.den);
    const int64_t twice_past = 2 * (g * r.num - k * 24 * r.den);  // 2 (time - k), x 24 den
    const int64_t nearest = twice_past > 24 * r.den ? k + 1 : k;  // a tie goes to k
    samples.push_back(static_cast<int32_t>(std::min<int64_t>(nearest, n - 1)));
  }
  return samples;
}

struct Expanded {
  TimingMap map;
  std::vector<int32_t> grid_frames;
};

// Source frame k shows the drawing of grid frame floor(k * 24 / R), while that grid frame is
// in the retimed grid sequence; source frames index the clip through `samples`. The gone
// frames: the sampled source frames of the grid's gone frames that no output frame shows.
Expanded RefExpand(const TimingMap& grid_map, const std::vector<int32_t>& samples, Rate r, int n) {
  Expanded out;
  std::set<int32_t> shown;
  for (int64_t k = 0; k < n; ++k) {
    const int64_t g = (k * 24 * r.den) / r.num;
    if (g >= static_cast<int64_t>(grid_map.source_frames.size())) break;
    const int32_t source = samples[grid_map.source_frames[g]];
    out.map.source_frames.push_back(source);
    out.map.kinds.push_back(grid_map.kinds[g]);
    out.grid_frames.push_back(static_cast<int32_t>(g));
    shown.insert(source);
  }
  std::set<int32_t> deleted, hidden;
  for (int32_t g : grid_map.deleted) {
    if (shown.count(samples[g]) == 0) deleted.insert(samples[g]);
  }
  for (int32_t g : grid_map.hidden) {
    if (shown.count(samples[g]) == 0 && deleted.count(samples[g]) == 0) hidden.insert(samples[g]);
  }
  out.map.deleted.assign(deleted.begin(), deleted.end());
  out.map.hidden.assign(hidden.begin(), hidden.end());
  out.map.omissions_applied = grid_map.omissions_applied;
  out.map.duplicates_applied = grid_map.duplicates_applied;
  out.map.duplicates_skipped = grid_map.duplicates_skipped;
  out.map.holds_applied = grid_map.holds_applied;
  out.map.duplicates_omitted = grid_map.duplicates_omitted;
  out.map.duplicates_held = grid_map.duplicates_held;
  return out;
}

enum class ClipStyle { kContinuous, kTinyIntegers, kStaticStretches, kIntegerWalk, kStill };

// frames x joints x 3 positions: random, with exact ties (tiny integers, walks) and static
// stretches (frames repeated for a while, so whole grid stretches have SSD 0).
std::vector<double> RandomPositions(SplitMix64& rng, int frames, int joints, ClipStyle style) {
  const size_t stride = static_cast<size_t>(joints) * 3;
  std::vector<double> p(static_cast<size_t>(frames) * stride, 0.0);
  int still_for = 0;
  for (int f = 0; f < frames; ++f) {
    double* frame = p.data() + f * stride;
    const double* prev = f > 0 ? frame - stride : nullptr;
    if (style == ClipStyle::kStaticStretches && still_for == 0 && rng.OneIn(4)) {
      still_for = rng.Int(1, 20);
    }
    const bool repeat = prev != nullptr && (style == ClipStyle::kStill || still_for > 0);
    if (still_for > 0) --still_for;
    for (size_t c = 0; c < stride; ++c) {
      if (repeat) {
        frame[c] = prev[c];
      } else if (style == ClipStyle::kContinuous || style == ClipStyle::kStaticStretches) {
        frame[c] = rng.Unit() * 2.0 - 1.0;
      } else if (style == ClipStyle::kTinyIntegers) {
        frame[c] = rng.Int(0, 2);
      } else {
        frame[c] = (prev != nullptr ? prev[c] : 0.0) + rng.Int(-1, 1);
      }
    }
  }
  return p;
}

// Frames samples[0], samples[1], ... of `positions`.
std::vector<double> Gather(const std::vector<double>& positions,
                           const std::vector<int32_t>& samples, int joints) {
  const size_t stride = static_cast<size_t>(joints) * 3;
  std::vector<double> out;
  for (int32_t s : samples) {
    out.insert(out.end(), positions.begin() + s * stride, positions.begin() + (s + 1) * stride);
  }
  return out;
}

RetimeOptions RandomOptions(SplitMix64& rng, int grid_frames) {
  if (rng.OneIn(4)) return DefaultRetimeOptions(grid_frames);
  RetimeOptions options;
  options.omissions = grid_frames >= 3 ? rng.Int(0, grid_frames - 3) : 0;
  options.holds = rng.Int(0, grid_frames);
  options.max_hold = rng.Int(1, 5);
  options.keep_length = !rng.OneIn(3);
  options.order = rng.OneIn(3) ? StepOrder::kHoldThenOmit : StepOrder::kOmitThenHold;
  return options;
}

std::string Describe(const TimingMap& map, const std::vector<int32_t>& grid_frames) {
  std::ostringstream out;
  for (size_t t = 0; t < map.source_frames.size(); ++t) {
    out << " " << map.source_frames[t] << "/" << static_cast<int>(map.kinds[t]);
    if (t < grid_frames.size()) out << "@" << grid_frames[t];
  }
  out << "\n  deleted:";
  for (int32_t f : map.deleted) out << " " << f;
  out << "\n  hidden:";
  for (int32_t f : map.hidden) out << " " << f;
  out << "\n  omissions " << map.omissions_applied << ", duplicates " << map.duplicates_applied
      << " (skipped " << map.duplicates_skipped << ", later omitted " << map.duplicates_omitted
      << ", later held " << map.duplicates_held << "), holds " << map.holds_applied;
  return out.str();
}

struct Clip {
  int frames = 0;
  int joints = 0;
  std::vector<double> positions;
};

// 2 .. 61 grid frames of 1 .. 3 joints at rate r.
Clip RandomClip(SplitMix64& rng, Rate r) {
  Clip clip;
  const int min_frames = static_cast<int>((24 * r.den + r.num - 1) / (24 * r.den)) + 1;
  const int max_frames = static_cast<int>(60 * r.num / (24 * r.den)) + 1;
  clip.frames = rng.Int(min_frames, max_frames);
  clip.joints = rng.Int(1, 3);
  clip.positions =
      RandomPositions(rng, clip.frames, clip.joints, static_cast<ClipStyle>(rng.Int(0, 4)));
  return clip;
}

// The equality property at rate r, on kClipsPerRate clips.
void CheckGridRetimingEqualsTheSampledClipExpanded(Rate r) {
  const std::optional<FilmGrid> grid = FilmGrid::Make(r.fps(), 24.0);
  ASSERT_EQ(grid.has_value(), r.num != 24 * r.den);
  int failures = 0;
  for (uint64_t seed = 1; seed <= kClipsPerRate && failures < 3; ++seed) {
    SplitMix64 rng(seed * 7919 + static_cast<uint64_t>(r.num));
    const Clip clip = RandomClip(rng, r);
    const std::vector<int32_t> ref_samples = RefSamples(r, clip.frames);
    const int grid_count = static_cast<int>(ref_samples.size());
    ASSERT_GE(grid_count, 2);
    const RetimeOptions options = RandomOptions(rng, grid_count);
    ASSERT_THAT(ValidateRetimeOptions(options, grid_count), koma::testing::IsOk());
    const std::string context = "seed " + std::to_string(seed) + ", " +
                                std::to_string(clip.frames) + " frames at " +
                                std::to_string(r.fps()) + " fps";

    // Reference: the 24 fps clip, retimed by the literal algorithm, expanded by the rule.
    const std::vector<double> sampled = Gather(clip.positions, ref_samples, clip.joints);
    ASSERT_OK_AND_ASSIGN(const FrameDistance sampled_distance,
                         FrameDistance::Create(sampled, grid_count, clip.joints, {}));
    const TimingMap grid_map = RetimeNaive(sampled_distance, options);
    const Expanded want = RefExpand(grid_map, ref_samples, r, clip.frames);

    // Under test: what the server does.
    GridRetimed got;
    if (grid) {
      const std::vector<int32_t> samples = GridSamples(*grid, clip.frames);
      ASSERT_EQ(samples, ref_samples) << context;
      const std::vector<double> gathered = Gather(clip.positions, samples, clip.joints);
      ASSERT_OK_AND_ASSIGN(
          const FrameDistance distance,
          FrameDistance::CreateView(gathered, static_cast<int>(samples.size()), clip.joints, {}));
      const TimingMap fast = RetimeFast(distance, options);
      got = ExpandGridTiming(fast, samples, *grid, clip.frames, /*at_source_rate=*/true);
      // At the timing rate: the grid map itself, in source frames.
      const GridRetimed at_grid =
          ExpandGridTiming(fast, samples, *grid, clip.frames, /*at_source_rate=*/false);
      ASSERT_EQ(at_grid.map.source_frames.size(), grid_map.source_frames.size()) << context;
      for (size_t t = 0; t < grid_map.source_frames.size(); ++t) {
        ASSERT_EQ(at_grid.map.source_frames[t], ref_samples[grid_map.source_frames[t]]);
        ASSERT_EQ(at_grid.map.kinds[t], grid_map.kinds[t]);
        ASSERT_EQ(at_grid.grid_frames[t], static_cast<int32_t>(t));
      }
    } else {  // 24 fps: no grid, the plain algorithm on the source
      ASSERT_OK_AND_ASSIGN(const FrameDistance distance,
                           FrameDistance::Create(clip.positions, clip.frames, clip.joints, {}));
      got.map = RetimeFast(distance, options);
      for (int t = 0; t < static_cast<int>(got.map.source_frames.size()); ++t) {
        got.grid_frames.push_back(t);
      }
    }
    if (r.num >= 24 * r.den) {
      // At or above 24 fps every grid frame has its source frames: each sampled frame is shown
      // or listed gone, once, and no other frame is either.
      std::vector<int> seen(static_cast<size_t>(clip.frames), 0);
      std::vector<bool> is_sample(static_cast<size_t>(clip.frames), false);
      for (int32_t f : ref_samples) is_sample[f] = true;
      for (int32_t f :
           std::set<int32_t>(got.map.source_frames.begin(), got.map.source_frames.end())) {
        ++seen[f];
      }
      for (int32_t f : got.map.deleted) ++seen[f];
      for (int32_t f : got.map.hidden) ++seen[f];
      for (int f = 0; f < clip.frames; ++f) {
        ASSERT_EQ(seen[f], is_sample[f] ? 1 : 0) << context << ": source frame " << f;
      }
    }
    if (!(got.map == want.map) || got.grid_frames != want.grid_frames) {
      ++failures;
      ADD_FAILURE() << context << "\nwant" << Describe(want.map, want.grid_frames) << "\ngot "
                    << Describe(got.map, got.grid_frames);
    }
  }
}

class RetimeGridPropertyTest : public ::testing::TestWithParam<Rate> {};

TEST_P(RetimeGridPropertyTest, GridRetimingEqualsRetimingTheSampledClipExpanded) {
  CheckGridRetimingEqualsTheSampledClipExpanded(GetParam());
}

TEST_P(RetimeGridPropertyTest, DefaultsShowEachDrawingForAGridFrameToMaxHoldInSeconds) {
  const Rate r = GetParam();
  const double source_frame_s = 1.0 / r.fps();
  const double grid_frame_s = 1.0 / 24.0;
  const std::optional<FilmGrid> grid = FilmGrid::Make(r.fps(), 24.0);
  int failures = 0;
  for (uint64_t seed = 1; seed <= kClipsPerRate && failures < 3; ++seed) {
    SplitMix64 rng(seed * 104729 + static_cast<uint64_t>(r.num));
    const Clip clip = RandomClip(rng, r);
    std::vector<int32_t> shown;  // per output frame at the source rate: its source frame
    RetimeOptions options;
    int skipped = 0;  // duplicates that found no gap: the output is that much shorter
    if (grid) {
      const std::vector<int32_t> samples = GridSamples(*grid, clip.frames);
      options = DefaultRetimeOptions(static_cast<int>(samples.size()));
      const std::vector<double> gathered = Gather(clip.positions, samples, clip.joints);
      ASSERT_OK_AND_ASSIGN(
          const FrameDistance distance,
          FrameDistance::Create(gathered, static_cast<int>(samples.size()), clip.joints, {}));
      const TimingMap grid_map = RetimeFast(distance, options);
      skipped = grid_map.duplicates_skipped;
      shown = ExpandGridTiming(grid_map, samples, *grid, clip.frames, true).map.source_frames;
    } else {
      options = DefaultRetimeOptions(clip.frames);
      ASSERT_OK_AND_ASSIGN(const FrameDistance distance,
                           FrameDistance::Create(clip.positions, clip.frames, clip.joints, {}));
      const TimingMap map = RetimeFast(distance, options);
      skipped = map.duplicates_skipped;
      shown = map.source_frames;
    }
    ASSERT_FALSE(shown.empty());
    if (skipped == 0) {
      EXPECT_EQ(shown.size(), static_cast<size_t>(clip.frames)) << "keep_length by default";
    }
    // Runs of one drawing, in seconds.
    std::vector<double> runs_s;
    for (size_t t = 0; t < shown.size(); ++t) {
      if (t > 0 && shown[t] == shown[t - 1]) {
        runs_s.back() += source_frame_s;
      } else {
        runs_s.push_back(source_frame_s);
      }
    }
    const double longest_s = options.max_hold * grid_frame_s + source_frame_s + 1e-9;
    const double shortest_s = grid_frame_s - source_frame_s - 1e-9;
    for (size_t i = 0; i < runs_s.size(); ++i) {
      const bool cut_by_the_end = i + 1 == runs_s.size();
      if ((!cut_by_the_end && runs_s[i] < shortest_s) || runs_s[i] > longest_s) {
        ++failures;
        ADD_FAILURE() << "seed " << seed << ", " << clip.frames << " frames at " << r.fps()
                      << " fps: drawing " << i << " of " << runs_s.size() << " is shown "
                      << runs_s[i] * 1000 << " ms, outside " << shortest_s * 1000 << " .. "
                      << longest_s * 1000 << " ms";
        break;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rates, RetimeGridPropertyTest, ::testing::ValuesIn(kRates), [](const auto& param_info) {
      return "Fps" + std::to_string(param_info.param.num) +
             (param_info.param.den == 1 ? "" : "_" + std::to_string(param_info.param.den));
    });

// Below 24 fps the grid is finer than the source (each source frame on about two grid
// frames, the ties going to the earlier frame): the same equality holds. (The seconds
// property does not: two grid frames sampling one source frame may be two runs on the grid.)
class RetimeGridUpsamplingTest : public ::testing::TestWithParam<Rate> {};

TEST_P(RetimeGridUpsamplingTest, GridRetimingEqualsRetimingTheSampledClipExpanded) {
  CheckGridRetimingEqualsTheSampledClipExpanded(GetParam());
}

const Rate kUpsamplingRates[] = {{12, 1}, {15, 1}, {10, 1}, {23976, 1000}};

INSTANTIATE_TEST_SUITE_P(Rates, RetimeGridUpsamplingTest, ::testing::ValuesIn(kUpsamplingRates),
                         [](const auto& param_info) {
                           return "Fps" + std::to_string(param_info.param.num) +
                                  (param_info.param.den == 1
                                       ? ""
                                       : "_" + std::to_string(param_info.param.den));
                         });

TEST(RetimeGridTest, OneHundredTwentyFpsDrawingsLastWholeGridFrames) {
  // 121 frames (1 s at 120 fps) of a point moving ever faster: the grid has 25 frames, and
  // every drawing at the source rate covers 5 source frames per grid frame it holds.
  const FilmGrid grid = *FilmGrid::Make(120.0, 24.0);
  std::vector<double> positions;
  for (int f = 0; f < 121; ++f) positions.insert(positions.end(), {f * f * 0.01, 0.0, 0.0});
  const std::vector<int32_t> samples = GridSamples(grid, 121);
  ASSERT_EQ(samples.size(), 25u);
  for (int g = 0; g < 25; ++g) EXPECT_EQ(samples[g], 5 * g);
  const std::vector<double> gathered = Gather(positions, samples, 1);
  ASSERT_OK_AND_ASSIGN(const FrameDistance distance, FrameDistance::Create(gathered, 25, 1, {}));
  const TimingMap grid_map = RetimeFast(distance, DefaultRetimeOptions(25));
  const GridRetimed out = ExpandGridTiming(grid_map, samples, grid, 121, true);
  ASSERT_EQ(out.map.source_frames.size(), 121u);
  for (int k = 0; k < 121; ++k) {
    ASSERT_EQ(out.grid_frames[k], std::min(k / 5, 24)) << k;
    ASSERT_EQ(out.map.source_frames[k], samples[grid_map.source_frames[k / 5]]) << k;
    ASSERT_EQ(out.map.source_frames[k] % 5, 0) << "only sampled frames are shown";
  }
  EXPECT_EQ(out.map.holds_applied, grid_map.holds_applied);
  EXPECT_GT(grid_map.holds_applied, 0);
}

}  // namespace
}  // namespace koma

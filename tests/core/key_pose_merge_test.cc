// Key poses that are poses (docs/semantics.md, "RetimeCurves", "Key poses"): keyframe times
// closer than a drawing merge into one key pose, so that on motions keyed the way Cubism
// animators key them (every curve on its own, at staggered times) "on threes" looks like
// threes. Hand-worked cases, a naive reference of the merge, and the acceptance measurements on
// generated Live2D-like motions at 30 and 60 fps.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/film_grid.h"
#include "core/koma_uchi.h"
#include "tests/testing/live2d_motion.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::testing::ElementsAre;

Curve Keyed(const std::string& id, std::vector<double> frames, int frame_count) {
  Curve curve;
  curve.id = id;
  curve.start = {frames.front(), 0.0};
  double value = 0.0;
  for (size_t i = 1; i < frames.size(); ++i) {
    CurveSegment s;
    s.type = SegmentType::kLinear;
    value = value == 0.0 ? 1.0 : 0.0;
    s.end = {frames[i], value};
    curve.segments.push_back(s);
  }
  if (frames.back() < frame_count - 1) {
    CurveSegment s;
    s.end = {static_cast<double>(frame_count - 1), value};
    curve.segments.push_back(s);
  }
  return curve;
}

KomaUchiResult Retime(const CurveSet& set, const KomaUchiOptions& options) {
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
  EXPECT_THAT(ValidateKomaUchiOptions(options, set), IsOk());
  return RetimeCurves(set, options);
}

std::vector<int> Holds(const DrawingTiming& timing) {
  std::vector<int> holds;
  for (size_t d = 0; d < timing.drawing_start.size(); ++d) {
    const int end = d + 1 < timing.drawing_start.size()
                        ? timing.drawing_start[d + 1]
                        : static_cast<int>(timing.drawing_of_frame.size());
    holds.push_back(end - timing.drawing_start[d]);
  }
  return holds;
}

TEST(PoseHoldLengthsTest, FloorOfLengthOverNLongerFirst) {
  EXPECT_THAT(PoseHoldLengths(10, 3), ElementsAre(4, 3, 3));
  EXPECT_THAT(PoseHoldLengths(9, 3), ElementsAre(3, 3, 3));
  EXPECT_THAT(PoseHoldLengths(5, 3), ElementsAre(5));
  EXPECT_THAT(PoseHoldLengths(2, 3), ElementsAre(2));  // shorter than a drawing: one drawing
  EXPECT_THAT(PoseHoldLengths(7, 2), ElementsAre(3, 2, 2));
  EXPECT_THAT(PoseHoldLengths(4, 1), ElementsAre(1, 1, 1, 1));
  EXPECT_TRUE(PoseHoldLengths(0, 3).empty());
  for (int n = 1; n <= 6; ++n) {
    for (int length = 1; length <= 80; ++length) {
      const std::vector<int> holds = PoseHoldLengths(length, n);
      int sum = 0;
      for (int h : holds) {
        sum += h;
        if (length >= n) {
          EXPECT_GE(h, n) << length << " on " << n;
        }
        EXPECT_LE(h - holds.back(), 1);
      }
      EXPECT_EQ(sum, length);
    }
  }
}

// The worked example of docs/semantics.md: shoulder keyed at 10 and 40, the arm a frame later
// (11, 41), the hand two frames after that (13, 43), hair at 16 and 46; 61 frames on threes,
// counted in source frames. Key poses: 0, 10 (shoulder, arm: 11 - 10 < 3), 13 (hand: 13 - 10
// is not < 3), 16 (hair), 40 (+41), 43, 46, 60. Every drawing lasts 3 frames or more.
TEST(KeyPoseMergeTest, StaggeredKeysFormOnePosePerDrawing) {
  CurveSet set;
  set.fps = 30.0;
  set.frame_count = 61;
  set.curves = {Keyed("ParamShoulderY", {0, 10, 40}, 61), Keyed("ParamArmLA", {0, 11, 41}, 61),
                Keyed("ParamHandL", {0, 13, 43}, 61), Keyed("ParamHairFront", {0, 16, 46}, 61),
                Keyed("ParamBreath", {0, 59}, 61)};
  KomaUchiOptions options;
  options.timing_fps = 0.0;
  const KomaUchiResult merged = Retime(set, options);
  EXPECT_THAT(merged.key_frames, ElementsAre(0, 10, 13, 16, 40, 43, 46, 60));
  // 59 is less than 3 frames before the clip's end: it joins the last frame's pose.
  EXPECT_THAT(merged.key_merged, ElementsAre(1, 2, 1, 1, 2, 1, 1, 2));
  const std::vector<int> holds = Holds(merged.timings[0]);
  // [0, 10]: 4, 3, 3; [10, 13], [13, 16]: 3; [16, 40]: eight 3s; [40, 43], [43, 46]: 3;
  // [46, 60]: 4, 4, 3, 3; the last frame's own drawing.
  EXPECT_THAT(holds, ElementsAre(4, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 4, 4, 3, 3, 1));
  // Each key pose starts a drawing that samples exactly its time.
  for (int key : merged.key_frames) {
    const DrawingTiming& t = merged.timings[0];
    EXPECT_EQ(t.drawing_start[t.drawing_of_frame[key]], key);
    EXPECT_EQ(t.source_frame[key], key);
  }
  // Merging off: every keyframe time is a pose, and 10, 11, 13 give 1- and 2-frame drawings.
  options.merge_key_poses = false;
  const KomaUchiResult unmerged = Retime(set, options);
  EXPECT_THAT(unmerged.key_frames,
              ElementsAre(0, 10, 11, 13, 16, 40, 41, 43, 46, 59, 60));
  EXPECT_TRUE(unmerged.key_merged.empty());
  const std::vector<int> unmerged_holds = Holds(unmerged.timings[0]);
  EXPECT_EQ(*std::min_element(unmerged_holds.begin(), unmerged_holds.end() - 1), 1);
}

// Named key poses are taken as they are, as before merging existed (the paper's experiment:
// tests/core/koma_uchi_test.cc).
TEST(KeyPoseMergeTest, NamedKeyPosesAreNotMerged) {
  CurveSet set;
  set.frame_count = 31;
  set.curves = {Keyed("A", {0, 5, 6, 7}, 31)};
  KomaUchiOptions named;
  named.timing_fps = 0.0;
  named.key_frames = {5, 6, 7};
  const KomaUchiResult result = Retime(set, named);
  EXPECT_THAT(result.key_frames, ElementsAre(0, 5, 6, 7, 30));
  EXPECT_TRUE(result.key_merged.empty());
  named.merge_key_poses = false;
  const KomaUchiResult off = Retime(set, named);
  EXPECT_EQ(off.timings[0].drawing_of_frame, result.timings[0].drawing_of_frame);
  EXPECT_EQ(off.curves[0].values, result.curves[0].values);
}

// The merge written out literally, on the key times mapped to the timing's frames: walk the
// times in order, open a new pose when the time is at least n after the last pose and at least
// n before the end, else count it into the pose before it (or the end's).
struct NaiveMerge {
  std::vector<int> poses;
  std::vector<int> counts;
};
NaiveMerge NaiveMergeOf(const std::vector<int>& times, int last, int n) {
  NaiveMerge out;
  out.poses = {0};
  out.counts = {0};
  int end_count = 1;
  for (size_t i = 0; i + 1 < times.size(); ++i) {  // the last is the clip's last frame
    const int t = times[i];
    if (t - out.poses.back() < n) {
      ++out.counts.back();
    } else if (last - t < n) {
      ++end_count;
    } else {
      out.poses.push_back(t);
      out.counts.push_back(1);
    }
  }
  out.poses.push_back(last);
  out.counts.push_back(end_count);
  return out;
}

TEST(KeyPoseMergeTest, AgreesWithNaiveMergeOnGeneratedMotions) {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    for (double fps : {30.0, 60.0}) {
      for (int n : {1, 2, 3, 4}) {
        const CurveSet set = testing::Live2dMotion({fps, 40, 3.0, seed});
        KomaUchiOptions options;
        options.frames_per_drawing = n;
        options.timing_fps = 24.0;
        const GridKeyPoses got = KeyPosesOnGrid(options, set);
        const FilmGrid grid = *FilmGrid::Make(fps, 24.0);
        const int last = grid.GridFrameCount(set.frame_count) - 1;
        // Every keyframe time, rounded to a source frame (distinct), then to the grid.
        std::set<int> source;
        for (const Curve& c : set.curves) {
          source.insert(static_cast<int>(c.start.frame + 0.5));
          for (const CurveSegment& s : c.segments) {
            source.insert(std::min(set.frame_count - 1, static_cast<int>(s.end.frame + 0.5)));
          }
        }
        source.insert(0);
        std::vector<int> times;
        for (int k : source) {
          if (k == set.frame_count - 1) continue;
          times.push_back(std::min(grid.NearestGridFrame(k), last));
        }
        times.push_back(last);
        const NaiveMerge want = NaiveMergeOf(times, last, n);
        EXPECT_EQ(got.grid, want.poses) << "seed " << seed << " fps " << fps << " n " << n;
        EXPECT_EQ(got.merged, want.counts) << "seed " << seed << " fps " << fps << " n " << n;
        for (size_t i = 1; i < got.grid.size(); ++i) {
          if (i + 1 < got.grid.size()) {
            EXPECT_GE(got.grid[i] - got.grid[i - 1], n);
          }
          EXPECT_GE(got.source[i], got.source[i - 1]);
        }
      }
    }
  }
}

// Visible drawings of one retimed curve: runs of one value, in grid frames (source frames
// without a grid). Their lengths, in order.
std::vector<int> VisibleDrawings(const RetimedCurve& curve, const DrawingTiming& timing,
                                 int grid_frames) {
  const std::vector<int>& starts =
      timing.drawing_start_grid.empty() ? timing.drawing_start : timing.drawing_start_grid;
  std::vector<int> lengths;
  int run_start = 0;
  for (size_t d = 1; d < starts.size(); ++d) {
    if (curve.steps[d].value != curve.steps[d - 1].value) {
      lengths.push_back(starts[d] - run_start);
      run_start = starts[d];
    }
  }
  lengths.push_back(grid_frames - run_start);
  return lengths;
}

bool Moves(const Curve& curve, const CurveSet& set) {
  const std::vector<double> v = SampleEveryFrame(curve, set.frame_count, set.beziers_restricted);
  return *std::min_element(v.begin(), v.end()) != *std::max_element(v.begin(), v.end());
}

double Quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1))];
}

// The acceptance: motions of 40-80 curves keyed at staggered times, at 30 and 60 fps.
// On threes, across all moving curves: no drawing shorter than 3 grid frames but at the clip's
// end, at most 8 drawings a second plus what the clip's end adds; on twos likewise with 2 and
// 12. Merging off (every keyframe time a pose, as before) shows the problem on the same
// motions, so the generator is as dense as real motions.
TEST(KeyPoseMergeTest, GeneratedLive2dMotionsAreOnThreesAndTwos) {
  for (int n : {3, 2}) {
    std::vector<double> merged_rates, unmerged_rates;
    int curves_checked = 0;
    for (uint64_t seed = 1; seed <= 16; ++seed) {
      for (double fps : {30.0, 60.0}) {
        const int curve_count = 40 + static_cast<int>((seed * 7) % 41);  // 40 .. 80
        const CurveSet set = testing::Live2dMotion({fps, curve_count, 4.0 + seed % 4, seed});
        ASSERT_EQ(static_cast<int>(set.curves.size()), curve_count);
        KomaUchiOptions options;
        options.frames_per_drawing = n;  // default grid: 24 fps
        options.timing_fps = 24.0;
        const int grid_frames = FilmGrid::Make(fps, 24.0)->GridFrameCount(set.frame_count);
        const double seconds = (grid_frames - 1) / 24.0;
        const KomaUchiResult merged = Retime(set, options);
        options.merge_key_poses = false;
        const KomaUchiResult unmerged = Retime(set, options);
        for (size_t c = 0; c < set.curves.size(); ++c) {
          if (!Moves(set.curves[c], set)) continue;
          ++curves_checked;
          const std::vector<int> drawings =
              VisibleDrawings(merged.curves[c], merged.timings[0], grid_frames);
          for (size_t i = 0; i + 1 < drawings.size(); ++i) {
            EXPECT_GE(drawings[i], n) << set.curves[c].id << " seed " << seed << " fps " << fps
                                      << " drawing " << i << " of " << drawings.size();
          }
          // Drawings of n frames or more over grid_frames - 1 frames, plus the last frame's.
          EXPECT_LE(static_cast<int>(drawings.size()), (grid_frames - 1) / n + 1);
          merged_rates.push_back(static_cast<double>(drawings.size()) / seconds);
          unmerged_rates.push_back(
              static_cast<double>(
                  VisibleDrawings(unmerged.curves[c], unmerged.timings[0], grid_frames).size()) /
              seconds);
        }
      }
    }
    std::ostringstream figures;
    figures << "on " << n << "s, " << curves_checked
            << " moving curves, drawings a second (median / p75 / p95 / max): merged "
            << Quantile(merged_rates, 0.5) << " / " << Quantile(merged_rates, 0.75) << " / "
            << Quantile(merged_rates, 0.95) << " / " << Quantile(merged_rates, 1.0)
            << "; every keyframe a pose " << Quantile(unmerged_rates, 0.5) << " / "
            << Quantile(unmerged_rates, 0.75) << " / " << Quantile(unmerged_rates, 0.95) << " / "
            << Quantile(unmerged_rates, 1.0);
    std::cout << figures.str() << "\n";
    ::testing::Test::RecordProperty("on_" + std::to_string(n) + "s", figures.str());
    EXPECT_GT(curves_checked, 1000);
    EXPECT_GT(Quantile(unmerged_rates, 0.95), 24.0 / n + 1.0);  // the problem, before
    EXPECT_LE(Quantile(merged_rates, 1.0), 24.0 / n + 1.0);
  }
}

// Each key pose starts a drawing exactly on its grid time, and shows the curves at the key
// pose's own time (its source frame), not the grid frame's.
TEST(KeyPoseMergeTest, EveryMergedKeyPoseStartsADrawingOnItsTime) {
  for (uint64_t seed = 20; seed < 26; ++seed) {
    const CurveSet set = testing::Live2dMotion({30.0, 50, 4.0, seed});
    KomaUchiOptions options;
    options.timing_fps = 24.0;
    const KomaUchiResult result = Retime(set, options);
    const DrawingTiming& t = result.timings[0];
    ASSERT_EQ(result.key_grid_frames.size(), result.key_frames.size());
    ASSERT_EQ(result.key_merged.size(), result.key_frames.size());
    for (size_t k = 0; k < result.key_grid_frames.size(); ++k) {
      const auto it = std::find(t.drawing_start_grid.begin(), t.drawing_start_grid.end(),
                                result.key_grid_frames[k]);
      ASSERT_NE(it, t.drawing_start_grid.end()) << "key " << k;
      const size_t d = static_cast<size_t>(it - t.drawing_start_grid.begin());
      EXPECT_EQ(t.drawing_tau[d], result.key_frames[k]);
      EXPECT_GE(result.key_merged[k], 1);
    }
  }
}

}  // namespace
}  // namespace koma

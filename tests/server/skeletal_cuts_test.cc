// RetimeSkeletal on real takes (docs/semantics.md, "Real takes"), through an in-process channel
// to the real service, on clips built from the real BVHs of tests/testdata and the samples: a
// T-pose frame prepended, two takes concatenated, a 40-second take, a glitch frame. Cuts split
// them into shots retimed as if alone; clean clips answer as without cuts, byte for byte; the
// omission rate scales with the take; the drawing rates give median holds of 2 and 3.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "convert/skeletal_convert.h"
#include "core/retime_shots.h"
#include "core/skeleton.h"
#include "formats/bvh.h"
#include "koma/v1/retime.grpc.pb.h"
#include "tests/formats/test_files.h"
#include "tests/server/in_process_server.h"
#include "tests/server/real_takes.h"

namespace koma::server {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using namespace ::koma::testing::real_takes;  // NOLINT: the takes' helpers, named as before

// The request of the paper's algorithm (a count named: max_hold 3), whose counts the shots share
// (the anime defaults are rates, tested in skeletal_defaults_test.cc).
v1::RetimeSkeletalRequest PaperRequestOf(const SkeletalClip& clip) {
  v1::RetimeSkeletalRequest request = RequestOf(clip);
  request.set_max_hold(3);
  return request;
}

class SkeletalCutsTest : public SkeletalServerTest {
 protected:
  // The clip retimed alone with these counts (cuts off, so it is the paper's algorithm).
  v1::RetimeSkeletalResponse Alone(const SkeletalClip& clip, int omissions, int holds) {
    v1::RetimeSkeletalRequest request = RequestOf(clip);
    request.set_omissions(omissions);
    request.set_holds(holds);
    request.set_cut_neighbour_ratio(0);
    return Call(request);
  }
};

// The response's timing map (in source frames of the whole clip) equals the shots' own
// responses concatenated, each offset by its first frame.
void ExpectConcatenation(const v1::RetimeSkeletalResponse& whole,
                         const std::vector<std::pair<int, v1::RetimeSkeletalResponse>>& shots) {
  std::vector<int> source, deleted, hidden, kinds;
  int omitted = 0, duplicated = 0, held = 0, duplicates_omitted = 0, duplicates_held = 0;
  for (const auto& [first, shot] : shots) {
    for (int s : shot.source_frames()) source.push_back(s + first);
    for (int k : shot.kinds()) kinds.push_back(k);
    for (int s : shot.deleted_frames()) deleted.push_back(s + first);
    for (int s : shot.hidden_frames()) hidden.push_back(s + first);
    omitted += shot.omissions_applied();
    duplicated += shot.duplicates_applied();
    held += shot.holds_applied();
    duplicates_omitted += shot.duplicates_omitted();
    duplicates_held += shot.duplicates_held();
  }
  EXPECT_EQ(std::vector<int>(whole.source_frames().begin(), whole.source_frames().end()), source);
  EXPECT_EQ(std::vector<int>(whole.kinds().begin(), whole.kinds().end()), kinds);
  EXPECT_EQ(std::vector<int>(whole.deleted_frames().begin(), whole.deleted_frames().end()),
            deleted);
  EXPECT_EQ(std::vector<int>(whole.hidden_frames().begin(), whole.hidden_frames().end()), hidden);
  EXPECT_EQ(whole.omissions_applied(), omitted);
  EXPECT_EQ(whole.duplicates_applied(), duplicated);
  EXPECT_EQ(whole.holds_applied(), held);
  EXPECT_EQ(whole.duplicates_omitted(), duplicates_omitted);
  EXPECT_EQ(whole.duplicates_held(), duplicates_held);
}

// What a lone frame's shot answers: itself, unchanged.
v1::RetimeSkeletalResponse LoneFrame() {
  v1::RetimeSkeletalResponse lone;
  lone.add_source_frames(0);
  lone.add_kinds(v1::ORIGINAL);
  return lone;
}

// No deleted frame is a shot's first or last source frame, nor a lone frame.
void ExpectOmissionsInsideShots(const v1::RetimeSkeletalResponse& r, int frame_count) {
  std::vector<int> bounds{0};
  for (int c : r.cut_frames()) {
    bounds.push_back(c - 1);
    bounds.push_back(c);
  }
  bounds.push_back(frame_count - 1);
  EXPECT_GT(r.omissions_applied(), 0);
  for (int d : r.deleted_frames()) {
    EXPECT_EQ(std::count(bounds.begin(), bounds.end(), d), 0) << "deleted frame " << d;
  }
}

// The grid frames of `clip` (30 fps: test1) on the 24 fps grid.
int GridFramesOf(int source_frames_at_30) { return (source_frames_at_30 - 1) * 24 / 30 + 1; }

TEST_F(SkeletalCutsTest, CleanClipsHaveNoCutsAndTheSameBytes) {
  for (const std::string& path : CleanClipPaths()) {
    for (double timing_fps : {24.0, 0.0}) {
      v1::RetimeSkeletalRequest request = RequestOf(ReadClip(path));
      request.set_timing_fps(timing_fps);
      const v1::RetimeSkeletalResponse with_rule = Call(request);
      request.set_cut_neighbour_ratio(0);
      const v1::RetimeSkeletalResponse without = Call(request);
      EXPECT_THAT(with_rule.cut_frames(), IsEmpty()) << path;
      EXPECT_EQ(with_rule.SerializeAsString(), without.SerializeAsString()) << path;
    }
  }
}

TEST_F(SkeletalCutsTest, CalibrationFrameFirstIsACutAndComesOutAsItWentIn) {
  const SkeletalClip walk = Test1();
  const SkeletalClip clip = Concat(TPoseAt(walk, 0), walk);
  const v1::RetimeSkeletalResponse r = Call(PaperRequestOf(clip));
  EXPECT_THAT(r.cut_frames(), ElementsAre(1));
  ASSERT_EQ(r.source_frames_size(), clip.frame_count);
  EXPECT_EQ(r.source_frames(0), 0);
  EXPECT_EQ(r.kinds(0), v1::ORIGINAL);
  EXPECT_EQ(std::count(r.source_frames().begin(), r.source_frames().end(), 0), 1);
  ExpectOmissionsInsideShots(r, clip.frame_count);
  // The walk gets every omission and hold of the whole clip: its shot is the only one long
  // enough to retime.
  const int grid = GridFramesOf(clip.frame_count);
  ExpectConcatenation(r, {{0, LoneFrame()}, {1, Alone(walk, std::min(4, grid - 3), grid / 3)}});
  // The motion: frame 0 the T-pose's channels, unchanged.
  const int n = PerFrame(clip);
  ASSERT_EQ(r.motion().channels().values_size(), clip.frame_count * n);
  for (int c = 0; c < n; ++c) EXPECT_EQ(r.motion().channels().values(c), clip.values[c]);
}

TEST_F(SkeletalCutsTest, CalibrationFrameLastIsACut) {
  const SkeletalClip walk = Test1();
  const SkeletalClip clip = Concat(walk, TPoseAt(walk, walk.frame_count - 1));
  const v1::RetimeSkeletalResponse r = Call(RequestOf(clip));
  EXPECT_THAT(r.cut_frames(), ElementsAre(walk.frame_count));
  EXPECT_EQ(r.source_frames(clip.frame_count - 1), walk.frame_count);
  EXPECT_EQ(r.kinds(clip.frame_count - 1), v1::ORIGINAL);
  ExpectOmissionsInsideShots(r, clip.frame_count);
}

TEST_F(SkeletalCutsTest, TwoTakesAreRetimedAloneWithTheCountsSplitByLength) {
  const SkeletalClip full = Test1();
  // Two takes of different lengths, the second elsewhere on the stage and played backwards.
  const SkeletalClip a = Frames(full, 0, 45);
  const SkeletalClip b = Moved(Reversed(full), 80.0);
  const SkeletalClip clip = Concat(a, b);
  for (const bool papers_defaults : {true, false}) {
    v1::RetimeSkeletalRequest request = PaperRequestOf(clip);
    const int grid = GridFramesOf(clip.frame_count);
    int omissions = std::min(4, grid - 3);
    int holds = grid / 3;
    if (!papers_defaults) {
      request.set_omissions(omissions = 9);
      request.set_holds(holds = 50);
    }
    const v1::RetimeSkeletalResponse r = Call(request);
    ASSERT_THAT(r.cut_frames(), ElementsAre(a.frame_count));
    EXPECT_EQ(r.omissions_requested(), omissions);
    EXPECT_EQ(r.holds_requested(), holds);
    const std::vector<int> lengths{GridFramesOf(a.frame_count), GridFramesOf(b.frame_count)};
    const std::vector<int> o = SplitByLength(omissions, lengths);
    const std::vector<int> h = SplitByLength(holds, lengths);
    ExpectConcatenation(r, {{0, Alone(a, o[0], h[0])}, {a.frame_count, Alone(b, o[1], h[1])}});
    ExpectOmissionsInsideShots(r, clip.frame_count);
  }
}

TEST_F(SkeletalCutsTest, GlitchFrameIsALoneShotThatPassesThrough) {
  const SkeletalClip full = Test1();
  const int g = 37;
  SkeletalClip clip = full;
  const SkeletalClip glitch = TPoseAt(full, g);
  const int n = PerFrame(clip);
  std::copy(glitch.values.begin(), glitch.values.end(), clip.values.begin() + g * n);
  const v1::RetimeSkeletalResponse r = Call(PaperRequestOf(clip));
  ASSERT_THAT(r.cut_frames(), ElementsAre(g, g + 1));
  EXPECT_EQ(r.source_frames(g), g);
  EXPECT_EQ(std::count(r.source_frames().begin(), r.source_frames().end(), g), 1);
  ExpectOmissionsInsideShots(r, clip.frame_count);
  const int grid = GridFramesOf(clip.frame_count);
  const std::vector<int> lengths{GridFramesOf(g), 1, GridFramesOf(full.frame_count - g - 1)};
  const std::vector<int> o = SplitByLength(std::min(4, grid - 3), {lengths[0], 0, lengths[2]});
  const std::vector<int> h = SplitByLength(grid / 3, {lengths[0], 0, lengths[2]});
  ExpectConcatenation(r, {{0, Alone(Frames(clip, 0, g), o[0], h[0])},
                          {g, LoneFrame()},
                          {g + 1, Alone(Frames(clip, g + 1, full.frame_count - g - 1), o[2], h[2])}});
}

TEST_F(SkeletalCutsTest, FortySecondTakeHasNoCutsAndTheRateScalesTheOmissions) {
  // test1 played forwards and backwards (no jump at the turns) for 40 s at 30 fps.
  const SkeletalClip full = Test1();
  const SkeletalClip back = Frames(Reversed(full), 1, full.frame_count - 1);
  SkeletalClip take = full;
  while (take.frame_count < 1200) take = Concat(take, (take.frame_count / 74) % 2 ? back : Frames(full, 1, 74));
  take = Frames(take, 0, 1200);
  EXPECT_EQ(Call(PaperRequestOf(take)).omissions_applied(), 4);  // the paper's count, per clip
  v1::RetimeSkeletalRequest request = RequestOf(take);
  request.set_omissions_per_second(1.0);  // the default rate, named
  const v1::RetimeSkeletalResponse rate = Call(request);
  EXPECT_THAT(rate.cut_frames(), IsEmpty());
  EXPECT_EQ(rate.grid_source_frames_size(), 960);
  EXPECT_EQ(rate.omissions_requested(), 40);  // 960 grid frames = 40 s
  EXPECT_EQ(rate.omissions_applied(), 40);
  // The same rate on the 2.5 s take: 60 grid frames, 2.5 -> 3.
  EXPECT_EQ(Call(RequestOf(full)).omissions_requested(), 3);
  // Counted in source frames: 1200 frames at 30 fps are 40 s too.
  request.set_timing_fps(0);
  EXPECT_EQ(Call(request).omissions_requested(), 40);
}

TEST_F(SkeletalCutsTest, CutsCanBeTurnedOffAndTuned) {
  const SkeletalClip walk = Test1();
  const SkeletalClip clip = Concat(TPoseAt(walk, 0), walk);
  v1::RetimeSkeletalRequest request = RequestOf(clip);
  request.set_cut_neighbour_ratio(0);
  EXPECT_THAT(Call(request).cut_frames(), IsEmpty());
  request.set_cut_neighbour_ratio(1e9);  // no pair is a billion times its neighbour
  EXPECT_THAT(Call(request).cut_frames(), IsEmpty());
  request.clear_cut_neighbour_ratio();
  request.set_cut_median_ratio(1e12);
  EXPECT_THAT(Call(request).cut_frames(), IsEmpty());
}

TEST_F(SkeletalCutsTest, DrawingRatesGiveMedianHoldsOfTwoAndThreeOnEveryRealClip) {
  std::vector<std::pair<std::string, SkeletalClip>> clips;
  for (const std::string& path : CleanClipPaths()) clips.push_back({path, ReadClip(path)});
  const SkeletalClip walk = Test1();
  clips.push_back({"T-pose + test1", Concat(TPoseAt(walk, 0), walk)});
  clips.push_back({"two takes", Concat(Frames(walk, 0, 45), Moved(Reversed(walk), 80.0))});
  for (const auto& [name, clip] : clips) {
    for (const auto& [rate, hold] : {std::pair<double, int>{12, 2}, {8, 3}}) {
      v1::RetimeSkeletalRequest request = RequestOf(clip);
      request.set_drawings_per_second(rate);
      request.set_output_rate(v1::TIMING_RATE);
      const v1::RetimeSkeletalResponse r = Call(request);
      const std::vector<int> runs = GridRuns(r);
      ASSERT_FALSE(runs.empty());
      EXPECT_EQ(runs[(runs.size() - 1) / 2], hold) << name << " at " << rate;
      EXPECT_EQ(runs[runs.size() / 2], hold) << name << " at " << rate;
      EXPECT_EQ(r.max_hold(), hold) << name;
      // About `rate` drawings a second of grid time: the target, but for a short tail run per
      // shot (the last frame is never held, so the run before it may stay short).
      const double seconds = r.source_frames_size() / 24.0;
      EXPECT_LE(runs.size(), rate * seconds + 2 * (1 + r.cut_frames_size()))
          << name << ": holds " << r.holds_applied() << " of " << r.holds_requested();
    }
  }
}

TEST_F(SkeletalCutsTest, DrawingRateWithoutAGridCountsSeconds) {
  // 120 fps counted in source frames: 8 drawings a second is a hold of 15 frames.
  v1::RetimeSkeletalRequest request = RequestOf(ReadClip(KOMA_TESTDATA_DIR "/bvh_test3.bvh"));
  request.set_timing_fps(0);
  request.set_drawings_per_second(8);
  const v1::RetimeSkeletalResponse r = Call(request);
  EXPECT_EQ(r.max_hold(), 15);
  EXPECT_EQ(GridRuns(r)[GridRuns(r).size() / 2], 15);
}

}  // namespace
}  // namespace koma::server

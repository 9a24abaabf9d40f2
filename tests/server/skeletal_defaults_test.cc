// RetimeSkeletal's defaults (docs/semantics.md, "Defaults: anime timing"), through an
// in-process channel to the real service. A request that names none of the paper's counts gets
// anime timing that scales with the take: on real takes at 30, 60 and 120 fps, 2.5 s to a
// minute long, a median hold of at least 2 grid frames, 7.5 to 12.5 drawings a second on the
// grid, at least one omission every two seconds, none at a shot's ends. A request that names a
// count gets the paper's algorithm exactly as before.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/retime.h"
#include "koma/v1/retime.grpc.pb.h"
#include "tests/server/in_process_server.h"
#include "tests/server/real_takes.h"

namespace koma::server {
namespace {

using namespace ::koma::testing::real_takes;  // NOLINT: the takes' helpers

using SkeletalDefaultsTest = SkeletalServerTest;

struct Take {
  std::string name;
  SkeletalClip clip;
};

// Every real clip, at 30, 60 and 120 fps, and long takes (20 s and 63 s) made from each by
// playing it forwards and backwards: 45 takes, 0.5 s to 63 s.
std::vector<Take> RealTakes() {
  std::vector<Take> takes;
  for (const std::string& path : CleanClipPaths()) {
    const SkeletalClip clip = ReadClip(path);
    const std::string name = path.substr(path.rfind('/') + 1);
    for (double fps : {30.0, 60.0, 120.0}) {
      const SkeletalClip at_rate = Resampled(clip, fps);
      const std::string rated = name + " at " + std::to_string(static_cast<int>(fps)) + " fps";
      takes.push_back({rated, at_rate});
      for (int seconds : {20, 63}) {
        takes.push_back({rated + ", " + std::to_string(seconds) + " s",
                         PingPong(at_rate, static_cast<int>(seconds * fps) + 1)});
      }
    }
  }
  return takes;
}

TEST_F(SkeletalDefaultsTest, EveryRealTakeComesOutInAnimeTimingThatScalesWithItsLength) {
  for (const Take& take : RealTakes()) {
    v1::RetimeSkeletalRequest request = RequestOf(take.clip);
    request.set_output_rate(v1::TIMING_RATE);  // one output frame per grid frame
    request.set_return_motion(false);
    const v1::RetimeSkeletalResponse r = Call(request);
    const std::vector<int> runs = GridRuns(r);
    ASSERT_FALSE(runs.empty()) << take.name;
    const double seconds = r.source_frames_size() / 24.0;
    EXPECT_GE(runs[(runs.size() - 1) / 2], 2) << take.name;
    EXPECT_GE(runs.size() / seconds, 7.5) << take.name;
    EXPECT_LE(runs.size() / seconds, 12.5) << take.name;
    EXPECT_GE(r.omissions_applied(), 0.5 * seconds) << take.name;
    EXPECT_EQ(r.omissions_per_second(), 1.0) << take.name;
    EXPECT_EQ(r.drawings_per_second(), 8.0) << take.name;
    // Inside the motion: never a shot's first or last frame (the takes here have no cut, so
    // the clip's ends).
    for (int deleted : r.deleted_frames()) {
      EXPECT_GT(deleted, 0) << take.name;
      EXPECT_LT(deleted, take.clip.frame_count - 1) << take.name;
    }
  }
}

// A calibration T-pose before a take: the omissions stay off the cut's two frames.
TEST_F(SkeletalDefaultsTest, NoOmissionNextToACut) {
  const SkeletalClip walk = Test1();
  const SkeletalClip clip = Concat(TPoseAt(walk, 0), PingPong(walk, 600));
  const v1::RetimeSkeletalResponse r = Call(RequestOf(clip));
  ASSERT_EQ(r.cut_frames_size(), 1);
  EXPECT_GE(r.omissions_applied(), 0.5 * r.grid_source_frames_size() / 24.0);
  for (int deleted : r.deleted_frames()) {
    EXPECT_NE(deleted, r.cut_frames(0) - 1);
    EXPECT_NE(deleted, r.cut_frames(0));
  }
}

// The defaults are exactly the two rates asked for by name.
TEST_F(SkeletalDefaultsTest, TheDefaultsAreTheRatesOneAndEight) {
  for (const std::string& path : CleanClipPaths()) {
    v1::RetimeSkeletalRequest request = RequestOf(ReadClip(path));
    const std::string defaults = Call(request).SerializeAsString();
    request.set_omissions_per_second(1.0);
    request.set_drawings_per_second(8.0);
    EXPECT_TRUE(Call(request).SerializeAsString() == defaults) << path;
    // Each rate given alone keeps the other's default.
    request.clear_drawings_per_second();
    EXPECT_TRUE(Call(request).SerializeAsString() == defaults) << path;
    request.clear_omissions_per_second();
    request.set_drawings_per_second(8.0);
    EXPECT_TRUE(Call(request).SerializeAsString() == defaults) << path;
  }
}

// Naming any count is the paper's algorithm: the paper's defaults for the other counts and no
// rate, as before the anime defaults existed (max_hold: 3 alone is `--preset paper`).
TEST_F(SkeletalDefaultsTest, NamingACountIsThePapersAlgorithm) {
  for (const std::string& path : CleanClipPaths()) {
    const SkeletalClip clip = ReadClip(path);
    v1::RetimeSkeletalRequest paper = RequestOf(clip);
    paper.set_max_hold(3);
    const v1::RetimeSkeletalResponse r = Call(paper);
    EXPECT_EQ(r.omissions_per_second(), 0.0) << path;
    EXPECT_EQ(r.drawings_per_second(), 0.0) << path;
    // The paper's counts of the counted frames: grid frames, or the source's at 24 fps.
    const RetimeOptions papers = DefaultRetimeOptions(
        r.timing_fps() > 0 ? r.grid_source_frames_size() : clip.frame_count);
    EXPECT_EQ(r.omissions_requested(), papers.omissions) << path;
    EXPECT_EQ(r.holds_requested(), papers.holds) << path;
    EXPECT_EQ(r.max_hold(), 3) << path;
    for (int count = 0; count < 3; ++count) {
      v1::RetimeSkeletalRequest named = RequestOf(clip);
      if (count == 0) named.set_omissions(papers.omissions);
      if (count == 1) named.set_holds(papers.holds);
      if (count == 2) named.set_max_hold(papers.max_hold);
      // Compared as bytes, reported briefly (the bytes hold the whole motion).
      EXPECT_TRUE(Call(named).SerializeAsString() == r.SerializeAsString())
          << path << ", count " << count;
    }
  }
}

}  // namespace
}  // namespace koma::server

// Real takes for the RetimeSkeletal tests (docs/semantics.md, "Real takes"), built from the
// real BVHs of tests/testdata and the samples: parts, concatenations, reversals, a T-pose, a
// take moved elsewhere, a take resampled to another rate, and what a response shows on the grid.
#ifndef KOMA_TESTS_SERVER_REAL_TAKES_H_
#define KOMA_TESTS_SERVER_REAL_TAKES_H_

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "convert/skeletal_convert.h"
#include "core/skeleton.h"
#include "formats/bvh.h"
#include "koma/v1/retime.pb.h"
#include "tests/formats/test_files.h"
#include "tests/server/in_process_server.h"

namespace koma::testing::real_takes {

inline SkeletalClip ReadClip(const std::string& path) {
  absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(formats::ReadTestFile(path));
  EXPECT_TRUE(clip.ok()) << path << ": " << clip.status();
  return clip.ok() ? *clip : SkeletalClip{};
}

inline SkeletalClip Test1() { return ReadClip(KOMA_TESTDATA_DIR "/bvh_test1.bvh"); }

// Every clean clip the project has: the real captures and the samples.
inline std::vector<std::string> CleanClipPaths() {
  return {KOMA_TESTDATA_DIR "/bvh_test1.bvh", KOMA_TESTDATA_DIR "/bvh_test2.bvh",
          KOMA_TESTDATA_DIR "/bvh_test3.bvh", KOMA_SAMPLES_DIR "/pitch.bvh",
          KOMA_SAMPLES_DIR "/mocap_120fps.bvh"};
}

inline int PerFrame(const SkeletalClip& clip) { return ChannelCount(clip.skeleton); }

// Frames [first, first + count) of `clip`.
inline SkeletalClip Frames(const SkeletalClip& clip, int first, int count) {
  SkeletalClip out = clip;
  const int n = PerFrame(clip);
  out.values.assign(clip.values.begin() + first * n, clip.values.begin() + (first + count) * n);
  out.frame_count = count;
  return out;
}

inline SkeletalClip Concat(const SkeletalClip& a, const SkeletalClip& b) {
  SkeletalClip out = a;
  out.values.insert(out.values.end(), b.values.begin(), b.values.end());
  out.frame_count = a.frame_count + b.frame_count;
  return out;
}

// The clip's frames in reverse order.
inline SkeletalClip Reversed(const SkeletalClip& clip) {
  SkeletalClip out = clip;
  const int n = PerFrame(clip);
  for (int f = 0; f < clip.frame_count; ++f) {
    std::copy_n(clip.values.begin() + (clip.frame_count - 1 - f) * n, n, out.values.begin() + f * n);
  }
  return out;
}

// Indices (within a frame) of the channels of `kind`.
inline std::vector<int> ChannelsWhere(const SkeletalClip& clip, bool rotation) {
  std::vector<int> out;
  int c = 0;
  for (const Joint& joint : clip.skeleton.joints) {
    for (ChannelKind kind : joint.channels) {
      const bool is_rotation = kind == ChannelKind::kXRotation || kind == ChannelKind::kYRotation ||
                               kind == ChannelKind::kZRotation;
      if (is_rotation == rotation) out.push_back(c);
      ++c;
    }
  }
  return out;
}

// A T-pose (every rotation 0: the BVH's bind pose) standing where frame `at` stands.
inline SkeletalClip TPoseAt(const SkeletalClip& clip, int at) {
  SkeletalClip pose = Frames(clip, at, 1);
  for (int c : ChannelsWhere(clip, true)) pose.values[c] = 0.0;
  return pose;
}

// The clip moved by `dx` along x (its root's position channels): another take, elsewhere.
inline SkeletalClip Moved(const SkeletalClip& clip, double dx) {
  SkeletalClip out = clip;
  const int n = PerFrame(clip);
  const int x = ChannelsWhere(clip, false).front();  // the root's Xposition
  for (int f = 0; f < clip.frame_count; ++f) out.values[f * n + x] += dx;
  return out;
}

inline v1::RetimeSkeletalRequest RequestOf(const SkeletalClip& clip) {
  v1::RetimeSkeletalRequest request;
  *request.mutable_motion() = convert::ToProto(clip);
  return request;
}

// The take resampled to `fps` (linear in every channel; a rotation takes the short way
// round): what a suit recording at another rate would give.
inline SkeletalClip Resampled(const SkeletalClip& clip, double fps) {
  const double source_fps = 1.0 / clip.frame_time;
  const int n = PerFrame(clip);
  const std::vector<int> rotations = ChannelsWhere(clip, true);
  const double seconds = (clip.frame_count - 1) / source_fps;
  const int frames = static_cast<int>(std::floor(seconds * fps + 1e-9)) + 1;
  SkeletalClip out = clip;
  out.frame_time = 1.0 / fps;
  out.frame_count = frames;
  out.values.assign(static_cast<size_t>(frames) * n, 0.0);
  for (int f = 0; f < frames; ++f) {
    const double at = f / fps * source_fps;
    const int a = std::min(static_cast<int>(at), clip.frame_count - 1);
    const int b = std::min(a + 1, clip.frame_count - 1);
    const double u = at - a;
    for (int c = 0; c < n; ++c) {
      const double x = clip.values[a * n + c];
      double d = clip.values[b * n + c] - x;
      if (std::count(rotations.begin(), rotations.end(), c) > 0) {
        d = std::remainder(d, 360.0);
      }
      out.values[f * n + c] = x + u * d;
    }
  }
  return out;
}

// The take played forwards and backwards (no jump at the turns) until it has `frames` frames:
// a long take with the take's own motion.
inline SkeletalClip PingPong(const SkeletalClip& clip, int frames) {
  const SkeletalClip forwards = Frames(clip, 1, clip.frame_count - 1);
  const SkeletalClip backwards = Frames(Reversed(clip), 1, clip.frame_count - 1);
  SkeletalClip take = clip;
  for (bool back = true; take.frame_count < frames; back = !back) {
    take = Concat(take, back ? backwards : forwards);
  }
  return Frames(take, 0, frames);
}

// Runs of one drawing on the grid (TIMING_RATE: one output frame per grid frame).
inline std::vector<int> GridRuns(const v1::RetimeSkeletalResponse& r) {
  std::vector<int> runs;
  for (int t = 0; t < r.source_frames_size(); ++t) {
    if (t == 0 || r.source_frames(t) != r.source_frames(t - 1)) runs.push_back(0);
    ++runs.back();
  }
  std::sort(runs.begin(), runs.end());
  return runs;
}

// A test with an in-process server: Call answers a RetimeSkeletal request (a failure fails
// the test).
class SkeletalServerTest : public ::testing::Test {
 protected:
  v1::RetimeSkeletalResponse Call(const v1::RetimeSkeletalRequest& request) {
    v1::RetimeSkeletalResponse response;
    const grpc::Status status = CallRpc(server_.stub(), request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }

  InProcessServer server_;
};

}  // namespace koma::testing::real_takes

#endif  // KOMA_TESTS_SERVER_REAL_TAKES_H_

// Forward kinematics (core/forward_kinematics.h) on a synthetic BVH-style clip: 31 joints in a
// chain-and-branch tree, a root with 6 channels and 30 joints with ZXY rotations (96 channels,
// like a CMU mocap skeleton), angles in [-180, 180) degrees from SplitMix64. A request in BVH
// channel form pays this once before retiming; `BM_SinCosDegrees` isolates the trigonometry.
#include <benchmark/benchmark.h>

#include <vector>

#include "core/forward_kinematics.h"
#include "core/split_mix64.h"
#include "core/trig_degrees.h"

namespace koma {
namespace {

constexpr int kJoints = 31;

Skeleton SyntheticSkeleton() {
  Skeleton skeleton;
  for (int j = 0; j < kJoints; ++j) {
    Joint joint;
    joint.name = "joint" + std::to_string(j);
    joint.parent = j == 0 ? -1 : (j % 5 == 1 ? 0 : j - 1);  // five chains from the root
    joint.offset = {0.0, 10.0, 1.0};
    if (j == 0) {
      joint.channels = {ChannelKind::kXPosition, ChannelKind::kYPosition, ChannelKind::kZPosition};
    }
    for (ChannelKind kind :
         {ChannelKind::kZRotation, ChannelKind::kXRotation, ChannelKind::kYRotation}) {
      joint.channels.push_back(kind);
    }
    skeleton.joints.push_back(joint);
  }
  return skeleton;
}

std::vector<double> SyntheticValues(int frames, int channels) {
  SplitMix64 rng(1);
  std::vector<double> values(static_cast<size_t>(frames) * channels);
  for (double& v : values) v = (rng.Unit() - 0.5) * 360.0;
  return values;
}

void BM_ForwardKinematics(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const Skeleton skeleton = SyntheticSkeleton();
  const std::vector<double> values = SyntheticValues(frames, 3 + 3 * kJoints);
  for (auto _ : state) {
    auto positions = ComputeWorldPositions(skeleton, values, frames);
    benchmark::DoNotOptimize(positions);
  }
  state.SetItemsProcessed(state.iterations() * frames);
}
BENCHMARK(BM_ForwardKinematics)->Arg(129)->Arg(100000)->Unit(benchmark::kMicrosecond);

void BM_SinCosDegrees(benchmark::State& state) {
  const std::vector<double> angles = SyntheticValues(1, 4096);
  for (auto _ : state) {
    for (double a : angles) benchmark::DoNotOptimize(SinCosDegrees(a));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(angles.size()));
}
BENCHMARK(BM_SinCosDegrees);

void BM_SinCosDegreesBatch(benchmark::State& state) {
  const std::vector<double> angles = SyntheticValues(1, 4096);
  std::vector<double> sin(angles.size()), cos(angles.size());
  for (auto _ : state) {
    SinCosDegrees(angles.data(), static_cast<int>(angles.size()), sin.data(), cos.data());
    benchmark::DoNotOptimize(sin.data());
    benchmark::DoNotOptimize(cos.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(angles.size()));
}
BENCHMARK(BM_SinCosDegreesBatch);

}  // namespace
}  // namespace koma


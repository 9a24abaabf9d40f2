// RetimeSkeletal core costs on synthetic clips: RetimeNaive vs RetimeFast, the SSD floor
// (FrameDistance::InputSsd, which any implementation must at least compute) and the cost of
// building the FrameDistance. Results and how to run: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <utility>
#include <vector>

#include "core/distance.h"
#include "core/retime.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kJoints = 31;        // a typical mocap skeleton (CMU BVH has 31 joints)
constexpr int kPitchFrames = 129;  // the paper's longest clip
constexpr int kLongFrames = 100000;
constexpr int kOmissions = 4;    // the paper's default
constexpr int kPitchHolds = 43;  // 129 / 3

// Smooth, random-looking motion: every coordinate is a sum of three sinusoids with periods
// of 15-200 frames and amplitudes up to 30 units, so speeds vary along the clip.
std::vector<double> SyntheticPositions(int frames, int joints) {
  SplitMix64 rng(2012);  // only picks the waves' parameters
  struct Wave {
    double amplitude, omega, phase;
  };
  std::vector<Wave> waves(static_cast<size_t>(joints) * 3 * 3);
  for (Wave& w : waves) {
    w = {30.0 * rng.Unit(), 2.0 * kPi / (15.0 + 185.0 * rng.Unit()), 2.0 * kPi * rng.Unit()};
  }
  std::vector<double> positions(static_cast<size_t>(frames) * joints * 3);
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < joints * 3; ++c) {
      double value = 0.0;
      for (int k = 0; k < 3; ++k) {
        const Wave& w = waves[static_cast<size_t>(c) * 3 + k];
        value += w.amplitude * std::sin(w.omega * f + w.phase);
      }
      positions[static_cast<size_t>(f) * joints * 3 + c] = value;
    }
  }
  return positions;
}

FrameDistance SyntheticDistance(int frames) {
  const std::vector<double> positions = SyntheticPositions(frames, kJoints);
  auto distance = FrameDistance::Create(positions, frames, kJoints, {});
  if (!distance.ok()) std::abort();
  return *std::move(distance);
}

// Built once per size and reused by every benchmark.
const FrameDistance& CachedDistance(int frames) {
  static const FrameDistance* pitch = new FrameDistance(SyntheticDistance(kPitchFrames));
  static const FrameDistance* longer = new FrameDistance(SyntheticDistance(kLongFrames));
  return frames == kPitchFrames ? *pitch : *longer;
}

RetimeOptions BenchOptions(int frames, int holds) {
  RetimeOptions options = DefaultRetimeOptions(frames);
  options.omissions = kOmissions;
  options.holds = holds < 0 ? frames / 3 : holds;  // -1: the default N / 3
  return options;
}

// Arguments: {frames, holds} (holds -1 = N / 3).
void BM_RetimeNaive(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const FrameDistance& distance = CachedDistance(frames);
  const RetimeOptions options = BenchOptions(frames, static_cast<int>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(RetimeNaive(distance, options));
}

void BM_RetimeFast(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const FrameDistance& distance = CachedDistance(frames);
  const RetimeOptions options = BenchOptions(frames, static_cast<int>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(RetimeFast(distance, options));
}

// The floor: one dist() per adjacent pair of source frames.
void BM_InputSsd(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(distance.InputSsd());
}

// Validating and copying the world positions (no transforms).
void BM_FrameDistanceCreate(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const std::vector<double> positions = SyntheticPositions(frames, kJoints);
  for (auto _ : state) {
    benchmark::DoNotOptimize(FrameDistance::Create(positions, frames, kJoints, {}));
  }
}

BENCHMARK(BM_RetimeNaive)->Args({kPitchFrames, kPitchHolds})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RetimeFast)->Args({kPitchFrames, kPitchHolds})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_InputSsd)->Arg(kPitchFrames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameDistanceCreate)->Arg(kPitchFrames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RetimeNaive)->Args({kLongFrames, kPitchHolds})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({kLongFrames, kPitchHolds})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({kLongFrames, -1})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InputSsd)->Arg(kLongFrames)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameDistanceCreate)->Arg(kLongFrames)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace koma

BENCHMARK_MAIN();

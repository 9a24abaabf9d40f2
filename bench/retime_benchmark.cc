// RetimeSkeletal core costs on synthetic clips: RetimeNaive vs RetimeFast, the SSD floor
// (FrameDistance::InputSsd, which any implementation must at least compute) and the cost of
// building the FrameDistance. Results and how to run: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <utility>
#include <vector>

#include "core/distance.h"
#include "core/large_array.h"
#include "core/retime.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kJoints = 31;           // a typical mocap skeleton (CMU BVH has 31 joints)
constexpr int kPitchFrames = 129;     // the paper's longest clip
constexpr int kOmissions = 4;         // the paper's default
constexpr int kPitchHolds = 43;       // 129 / 3
constexpr int kManyOmissions = 1000;  // the performance target's Nio at 1M frames

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

// Built once per size (on first use) and reused by every benchmark; never freed. The 1M
// clip alone is 744 MB of positions.
const FrameDistance& CachedDistance(int frames) {
  static std::map<int, const FrameDistance*>* cache = new std::map<int, const FrameDistance*>;
  const FrameDistance*& slot = (*cache)[frames];
  if (slot == nullptr) slot = new FrameDistance(SyntheticDistance(frames));
  return *slot;
}

RetimeOptions BenchOptions(int frames, int holds, int omissions) {
  RetimeOptions options = DefaultRetimeOptions(frames);
  options.omissions = omissions;
  options.holds = holds < 0 ? frames / 3 : holds;  // -1: the default N / 3
  return options;
}

// Arguments: {frames, holds, omissions} (holds -1 = N / 3).
RetimeOptions StateOptions(const benchmark::State& state) {
  return BenchOptions(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                      static_cast<int>(state.range(2)));
}

void BM_RetimeNaive(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  const RetimeOptions options = StateOptions(state);
  for (auto _ : state) benchmark::DoNotOptimize(RetimeNaive(distance, options));
}

void BM_RetimeFast(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  const RetimeOptions options = StateOptions(state);
  for (auto _ : state) benchmark::DoNotOptimize(RetimeFast(distance, options));
}

// The floor: one dist() per adjacent pair of source frames.
void BM_InputSsd(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(distance.InputSsd());
}

// RetimeFast's streaming pass: three distances per frame (ssd, skip, skip2), into arrays kept
// across iterations so that only the pass is timed. At 10k frames the clip fits the L3 cache.
void BM_AdjacentDistances(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  LargeArray<double> ssd, skip, skip2;
  for (auto _ : state) {
    distance.AdjacentDistances(&ssd, &skip, &skip2);
    benchmark::DoNotOptimize(ssd.data());
  }
}

// The 1M target's ratio, measured pair by pair: each iteration times the SSD floor and then
// RetimeFast on the same clip, back to back, and the counters report the median of the
// per-pair ratios (and each side's median). On a shared host the load changes over seconds,
// so two separate benchmark runs can see different machines; a pair sees nearly the same one.
void BM_RetimeFastOverSsd(benchmark::State& state) {
  const FrameDistance& distance = CachedDistance(static_cast<int>(state.range(0)));
  const RetimeOptions options = StateOptions(state);
  std::vector<double> ratios, floor_ms, fast_ms;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(distance.InputSsd());
    const auto middle = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(RetimeFast(distance, options));
    const auto end = std::chrono::steady_clock::now();
    floor_ms.push_back(std::chrono::duration<double, std::milli>(middle - start).count());
    fast_ms.push_back(std::chrono::duration<double, std::milli>(end - middle).count());
    ratios.push_back(fast_ms.back() / floor_ms.back());
  }
  auto median = [](std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  };
  state.counters["ratio"] = median(ratios);
  state.counters["ssd_ms"] = median(floor_ms);
  state.counters["fast_ms"] = median(fast_ms);
}

// Validating and copying the world positions (no transforms).
void BM_FrameDistanceCreate(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  const std::vector<double> positions = SyntheticPositions(frames, kJoints);
  for (auto _ : state) {
    benchmark::DoNotOptimize(FrameDistance::Create(positions, frames, kJoints, {}));
  }
}

// Pitch size: the paper's longest clip.
BENCHMARK(BM_RetimeNaive)
    ->Args({kPitchFrames, kPitchHolds, kOmissions})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RetimeFast)
    ->Args({kPitchFrames, kPitchHolds, kOmissions})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_InputSsd)->Arg(kPitchFrames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FrameDistanceCreate)->Arg(kPitchFrames)->Unit(benchmark::kMicrosecond);

// 10k, 100k and 1M frames: the default Nhf = N/3 (-1), and the paper's Nhf 43 for scale.
// The naive form is quadratic at N/3 holds, so it runs at 10k only.
BENCHMARK(BM_RetimeNaive)->Args({10000, -1, kOmissions})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({10000, -1, kOmissions})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({10000, kPitchHolds, kOmissions})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InputSsd)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({100000, -1, kOmissions})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RetimeFast)->Args({100000, kPitchHolds, kOmissions})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InputSsd)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameDistanceCreate)->Arg(100000)->Unit(benchmark::kMillisecond);
// The performance target: 1M frames, Nio 1000, Nhf N/3, within 4x of the SSD floor.
BENCHMARK(BM_RetimeFast)
    ->Args({1000000, -1, kManyOmissions})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK(BM_RetimeFast)
    ->Args({1000000, -1, kOmissions})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK(BM_InputSsd)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(10);
BENCHMARK(BM_RetimeFastOverSsd)
    ->Args({1000000, -1, kManyOmissions})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(15);
BENCHMARK(BM_AdjacentDistances)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AdjacentDistances)->Arg(1000000)->Unit(benchmark::kMillisecond)->Iterations(10);

}  // namespace
}  // namespace koma


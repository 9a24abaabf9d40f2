// LipBlink core costs (docs/semantics.md, "LipBlink") on a long synthetic Live2D-style clip: one
// mouth curve with speech, two eye curves with blinks, 100,000 frames at 30 fps (55 min).
// Results and how to run: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "absl/types/span.h"
#include "core/lip_blink.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr int kFrames = 100000;  // 55 min at 30 fps
constexpr double kFps = 30.0;

// Utterances of 2-6 s (values random in [0, 1], a new target every 2-4 frames) separated by
// 1-3 s of rest at 0: about 70 % speech.
std::vector<double> Mouth() {
  SplitMix64 rng(3);
  std::vector<double> m;
  while (static_cast<int>(m.size()) < kFrames) {
    m.insert(m.end(), static_cast<size_t>(rng.Int(30, 90)), 0.0);
    for (int left = rng.Int(60, 180); left > 0;) {
      const int hold = std::min(left, rng.Int(2, 4));
      m.insert(m.end(), static_cast<size_t>(hold), rng.Unit());
      left -= hold;
    }
  }
  m.resize(kFrames);
  return m;
}

// Open (0.97-1) with a blink every 3-5 s: 1-2 frames half-shut, 2-3 closed, 2-4 opening. The
// right eye closes one frame later than the left one in half of the blinks, and spans
// 0.05-0.9 instead of 0-1.
std::vector<std::vector<double>> Eyes() {
  SplitMix64 rng(4);
  std::vector<double> left;
  std::vector<double> right;
  const auto push = [&](int count, double low, double high, int right_delay) {
    for (int i = 0; i < count; ++i) {
      const double v = low + (high - low) * rng.Unit();
      left.push_back(v);
      right.push_back(i < right_delay && !right.empty() ? right.back() : v);
    }
  };
  while (static_cast<int>(left.size()) < kFrames) {
    push(rng.Int(90, 150), 0.97, 1.0, 0);
    const int delay = rng.Int(0, 1);
    push(rng.Int(1, 2), 0.3, 0.7, delay);
    push(rng.Int(2, 3), 0.0, 0.05, delay);
    push(rng.Int(2, 4), 0.3, 0.7, 0);
  }
  left.resize(kFrames);
  right.resize(kFrames);
  for (double& v : right) v = 0.05 + 0.85 * v;
  return {left, right};
}

// Argument: 0 RANDOM, 1 FOLLOW; speech detected.
void BM_ConvertMouth(benchmark::State& state) {
  const std::vector<double> mouth = Mouth();
  MouthOptions options;
  options.mode = state.range(0) == 0 ? MouthMode::kRandom : MouthMode::kFollow;
  if (!ValidateMouthOptions(options, kFrames).ok()) std::abort();
  for (auto _ : state) benchmark::DoNotOptimize(ConvertMouth(mouth, options, 2019));
  state.SetItemsProcessed(state.iterations() * kFrames);
  const MouthResult r = ConvertMouth(mouth, options, 2019);
  state.counters["speech"] = static_cast<double>(r.speech.size());
  state.counters["holds"] = static_cast<double>(r.holds.size());
}

// Arguments: {linked, auto_blink}.
void BM_ConvertEyes(benchmark::State& state) {
  const std::vector<std::vector<double>> eyes = Eyes();
  const std::vector<absl::Span<const double>> spans(eyes.begin(), eyes.end());
  EyeOptions options;
  options.linked = state.range(0) != 0;
  options.auto_blink.enabled = state.range(1) != 0;
  options.fps = kFps;
  if (!ValidateEyeOptions(options, kFrames).ok()) std::abort();
  for (auto _ : state) benchmark::DoNotOptimize(ConvertEyes(spans, options, 2019));
  state.SetItemsProcessed(state.iterations() * kFrames * static_cast<int64_t>(eyes.size()));
  const EyeResult r = ConvertEyes(spans, options, 2019);
  const auto automatic = std::count_if(r.blinks[0].begin(), r.blinks[0].end(),
                                       [](const Blink& b) { return b.automatic; });
  state.counters["blinks"] = static_cast<double>(r.blinks[0].size());  // of the first curve
  state.counters["auto"] = static_cast<double>(automatic);
}

// The floor: allocating and copying one double per curve and frame, as the results must.
void BM_OutputFloor(benchmark::State& state) {
  const std::vector<double> source(kFrames, 0.5);
  for (auto _ : state) {
    std::vector<std::vector<double>> values(static_cast<size_t>(state.range(0)), source);
    benchmark::DoNotOptimize(values.data());
    benchmark::ClobberMemory();
  }
}

BENCHMARK(BM_ConvertMouth)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConvertEyes)->Args({1, 1})->Args({1, 0})->Args({0, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OutputFloor)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace koma


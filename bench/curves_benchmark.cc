// RetimeCurves core costs on synthetic Live2D-style motions: the whole retiming (key poses,
// timings, every curve sampled per drawing and held), EvaluateCurve alone, and the floor of
// writing the per-frame output. Results and how to run: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"
#include "core/split_mix64.h"

namespace koma {
namespace {

constexpr int kTypicalCurves = 60;   // a Live2D model's parameters in one motion
constexpr int kTypicalFrames = 300;  // 10 s at 30 fps
constexpr int kLargeCurves = 500;
constexpr int kLargeFrames = 10000;
constexpr int kEvaluations = 1000;  // times per EvaluateCurve benchmark iteration

// Pose-to-pose animation: every curve is keyed at the same pose times, 6-14 frames apart (a
// keyframe every ~10 frames), two thirds of the segments Bezier with handles a third of the way
// in (Cubism's editor default), the rest linear. Values are random in [-30, 30] (degrees).
CurveSet SyntheticMotion(int curve_count, int frame_count, bool beziers_restricted) {
  SplitMix64 rng(2019);
  std::vector<double> poses = {0.0};
  while (poses.back() < frame_count - 1) {
    poses.push_back(std::min<double>(poses.back() + rng.Int(6, 14), frame_count - 1));
  }
  CurveSet set;
  set.fps = 30.0;
  set.frame_count = frame_count;
  set.beziers_restricted = beziers_restricted;
  for (int c = 0; c < curve_count; ++c) {
    Curve curve;
    curve.id = "Param" + std::to_string(c);
    curve.start = {0.0, 60.0 * rng.Unit() - 30.0};
    for (size_t k = 1; k < poses.size(); ++k) {
      CurveSegment segment;
      const CurvePoint from = k == 1 ? curve.start : curve.segments.back().end;
      segment.end = {poses[k], 60.0 * rng.Unit() - 30.0};
      segment.type = rng.Int(0, 2) == 0 ? SegmentType::kLinear : SegmentType::kBezier;
      const double third = (segment.end.frame - from.frame) / 3.0;
      segment.handles[0] = {from.frame + third, from.value};
      segment.handles[1] = {segment.end.frame - third, segment.end.value};
      curve.segments.push_back(segment);
    }
    set.curves.push_back(std::move(curve));
  }
  if (!ValidateCurveSet(set).ok()) std::abort();
  return set;
}

// On threes with tame and tsume (the paper's setting), hair on twos.
KomaUchiOptions BenchOptions(const CurveSet& set, double timing_fps) {
  KomaUchiOptions options;
  options.timing_fps = timing_fps;
  options.frames_per_drawing = 3;
  options.tame = 1.5;
  options.tsume = 1.5;
  options.curve_frames_per_drawing[set.curves[0].id] = 2;
  if (!ValidateKomaUchiOptions(options, set).ok()) std::abort();
  return options;
}

// Arguments: {curves, frames, beziers_restricted, timing_fps}: the 30 fps motion counted in
// its own frames (0) or on the 24 fps film grid (24), side by side.
void BM_RetimeCurves(benchmark::State& state) {
  const CurveSet set = SyntheticMotion(static_cast<int>(state.range(0)),
                                       static_cast<int>(state.range(1)), state.range(2) != 0);
  const KomaUchiOptions options = BenchOptions(set, static_cast<double>(state.range(3)));
  for (auto _ : state) benchmark::DoNotOptimize(RetimeCurves(set, options));
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(1));  // values
}

// The floor: allocating and filling one double per curve and frame, as the result must.
void BM_OutputFloor(benchmark::State& state) {
  const size_t curves = static_cast<size_t>(state.range(0));
  const size_t frames = static_cast<size_t>(state.range(1));
  for (auto _ : state) {
    std::vector<std::vector<double>> values(curves);
    for (std::vector<double>& v : values) v.assign(frames, 1.0);
    benchmark::DoNotOptimize(values.data());
    benchmark::ClobberMemory();
  }
}

// One typical curve at kEvaluations random times (binary search for the segment each time).
// Argument: beziers_restricted.
void BM_EvaluateCurve(benchmark::State& state) {
  const CurveSet set = SyntheticMotion(1, kTypicalFrames, state.range(0) != 0);
  SplitMix64 rng(7);
  std::vector<double> times(kEvaluations);
  for (double& t : times) t = (kTypicalFrames - 1) * rng.Unit();
  for (auto _ : state) {
    for (double t : times) {
      benchmark::DoNotOptimize(EvaluateCurve(set.curves[0], t, set.beziers_restricted));
    }
  }
  state.SetItemsProcessed(state.iterations() * kEvaluations);
}

BENCHMARK(BM_RetimeCurves)
    ->Args({kTypicalCurves, kTypicalFrames, 1, 0})
    ->Args({kTypicalCurves, kTypicalFrames, 1, 24})
    ->Args({kTypicalCurves, kTypicalFrames, 0, 0})
    ->Args({kTypicalCurves, kTypicalFrames, 0, 24})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OutputFloor)->Args({kTypicalCurves, kTypicalFrames})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RetimeCurves)
    ->Args({kLargeCurves, kLargeFrames, 1, 0})
    ->Args({kLargeCurves, kLargeFrames, 1, 24})
    ->Args({kLargeCurves, kLargeFrames, 0, 0})
    ->Args({kLargeCurves, kLargeFrames, 0, 24})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OutputFloor)->Args({kLargeCurves, kLargeFrames})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateCurve)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace koma


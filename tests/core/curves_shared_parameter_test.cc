// RetimeCurves solves an unrestricted Bezier's parameter once for all the curves of a timing
// that have the same times (CurveCursor::EvaluateSharing, SameCurveTimes). Checked against the
// plain evaluation on 300 random sets: many curves share a few sets of times (with different
// values), some differ from a shared set in one handle frame, end frame or segment type, some
// are dense; restricted and unrestricted Beziers, with and without the 24 fps grid, curves with
// their own n (several timings). Every drawing's value must equal EvaluateCurve at the time
// the curve shows there (its tau, or one of its keys: core/key_drawings.h), bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/curve_cursor.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "core/key_drawings.h"
#include "core/koma_uchi.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;

uint64_t Bits(double x) {
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

// Keyframe times over [0, last]: Beziers (handles inside their segment and in order, so valid
// restricted too), linear and stepped segments.
Curve RandomTimes(SplitMix64& rng, int last) {
  Curve curve;
  double frame = rng.OneIn(3) ? 0.0 : rng.Int(0, 5) + (rng.OneIn(2) ? 0.5 : 0.0);
  curve.start = {frame, 0.0};
  while (true) {
    const double end = frame + rng.Int(1, 25) + (rng.OneIn(3) ? 0.25 : 0.0);
    if (end > last) break;
    CurveSegment segment;
    const int kind = rng.Int(0, 5);
    segment.type = kind == 0 ? SegmentType::kLinear
                   : kind == 1 ? SegmentType::kStepped
                               : SegmentType::kBezier;
    double a = frame + (end - frame) * rng.Unit(), b = frame + (end - frame) * rng.Unit();
    if (b < a) std::swap(a, b);
    segment.handles[0] = {a, 0.0};
    segment.handles[1] = {b, 0.0};
    segment.end = {end, 0.0};
    curve.segments.push_back(segment);
    frame = end;
  }
  return curve;
}

// The same times with random values.
Curve WithValues(SplitMix64& rng, Curve curve) {
  const auto value = [&rng] { return rng.OneIn(6) ? 1.0 : 200 * rng.Unit() - 100; };
  curve.start.value = value();
  for (CurveSegment& segment : curve.segments) {
    segment.handles[0].value = value();
    segment.handles[1].value = value();
    segment.end.value = value();
  }
  return curve;
}

// `curve` with one of its times changed a little (or its type), when it has a segment.
void Perturb(SplitMix64& rng, Curve& curve) {
  if (curve.segments.empty()) return;
  CurveSegment& segment = curve.segments[static_cast<size_t>(rng.Int(0, curve.segments.size() - 1))];
  switch (rng.Int(0, 3)) {
    case 0:  // a handle frame, a little earlier (still inside: handles[0] >= the segment start)
      segment.handles[1].frame = segment.handles[0].frame + (segment.handles[1].frame - segment.handles[0].frame) * 0.5;
      break;
    case 1:
      segment.handles[0].frame = std::nextafter(segment.handles[0].frame, segment.handles[1].frame);
      break;
    case 2:
      segment.type = segment.type == SegmentType::kBezier ? SegmentType::kLinear : SegmentType::kBezier;
      break;
    default:
      if (&segment == &curve.segments.back()) segment.end.frame += 0.5;
      break;
  }
}

TEST(CurvesSharedParameterTest, EveryDrawingEqualsThePlainEvaluation) {
  SplitMix64 rng(0x32C);
  int drawings_checked = 0, shared_curves = 0;
  for (int round = 0; round < 300; ++round) {
    CurveSet set;
    set.fps = rng.OneIn(2) ? 30.0 : 24.0;
    set.frame_count = rng.Int(12, 240);
    set.beziers_restricted = rng.OneIn(4);
    const int last = set.frame_count - 1;
    std::vector<Curve> shapes;
    const int shape_count = rng.Int(1, 4);
    for (int s = 0; s < shape_count; ++s) shapes.push_back(RandomTimes(rng, last));
    const int curve_count = rng.Int(1, 40);
    KomaUchiOptions options;
    options.frames_per_drawing = rng.Int(1, 4);
    options.tame = 1.0 + rng.Unit();
    options.tsume = 1.0 + rng.Unit();
    options.timing_fps = rng.OneIn(2) ? 24.0 : 0.0;
    for (int c = 0; c < curve_count; ++c) {
      Curve curve;
      if (rng.OneIn(15)) {
        curve.samples.resize(static_cast<size_t>(set.frame_count));
        for (double& v : curve.samples) v = rng.Unit();
      } else {
        curve = WithValues(rng, shapes[static_cast<size_t>(rng.Int(0, shape_count - 1))]);
        if (rng.OneIn(5)) Perturb(rng, curve);
        else ++shared_curves;
      }
      curve.id = absl::StrCat("c", c);
      if (rng.OneIn(6)) options.curve_frames_per_drawing[curve.id] = rng.Int(1, 4);
      set.curves.push_back(std::move(curve));
    }
    ASSERT_THAT(ValidateCurveSet(set), IsOk()) << round;
    ASSERT_THAT(ValidateKomaUchiOptions(options, set), IsOk()) << round;
    const KomaUchiResult result = RetimeCurves(set, options);
    ASSERT_EQ(result.curves.size(), set.curves.size());
    for (size_t c = 0; c < set.curves.size(); ++c) {
      const RetimedCurve& retimed = result.curves[c];
      const DrawingTiming& timing = result.timings[static_cast<size_t>(retimed.timing)];
      const bool on_grid = !timing.drawing_time.empty();
      ASSERT_GE(retimed.steps.size(), timing.drawing_start.size());
      // The times the curve shows (its keys placed as RetimeCurves places them), then each
      // drawing's value by the plain evaluation at its time, or the key it shows.
      const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
      std::vector<double> taus;
      for (size_t d = 0; d < timing.drawing_start.size(); ++d) {
        taus.push_back(on_grid ? timing.drawing_tau[d]
                               : timing.source_frame[static_cast<size_t>(timing.drawing_start[d])]);
      }
      std::vector<KeyDrawing> keys = KeysToDraw(set.curves[c]);
      for (KeyDrawing& key : keys) {
        if (grid) {
          const std::vector<int>& starts = timing.drawing_start_grid;
          const int g = std::min(grid->NearestGridFrame(key.frame), starts.back());
          key.drawing = static_cast<int>(std::upper_bound(starts.begin(), starts.end(), g) -
                                         starts.begin()) - 1;
        } else {
          key.drawing = timing.drawing_of_frame[static_cast<size_t>(std::clamp(
              std::round(key.frame), 0.0, static_cast<double>(set.frame_count - 1)))];
        }
      }
      const CurveDrawingTimes placed = PlaceKeysOnDrawings(std::move(keys), taus);
      ASSERT_GE(retimed.steps.size(), timing.drawing_start.size());
      for (size_t d = 0; d < timing.drawing_start.size(); ++d) {
        const double want =
            placed.at_key[d] >= 0
                ? placed.keys[static_cast<size_t>(placed.at_key[d])].value
                : EvaluateCurve(set.curves[c], placed.time[d], set.beziers_restricted);
        ASSERT_EQ(Bits(retimed.steps[d].value), Bits(want))
            << "round " << round << " curve " << c << " drawing " << d << " time "
            << placed.time[d];
        ++drawings_checked;
      }
      // Each drawing's value held over its frames.
      for (size_t d = 0; d < timing.drawing_start.size(); ++d) {
        const size_t begin = static_cast<size_t>(timing.drawing_start[d]);
        const size_t end = d + 1 < timing.drawing_start.size()
                               ? static_cast<size_t>(timing.drawing_start[d + 1])
                               : retimed.values.size();
        for (size_t f = begin; f < end; ++f) {
          ASSERT_EQ(Bits(retimed.values[f]), Bits(retimed.steps[d].value)) << round << " " << f;
        }
      }
    }
  }
  EXPECT_GT(drawings_checked, 50000);
  EXPECT_GT(shared_curves, 2000);
}

TEST(CurvesSharedParameterTest, SameCurveTimesComparesEveryTimeAndType) {
  SplitMix64 rng(5);
  Curve times;
  while (times.segments.size() < 3) times = RandomTimes(rng, 200);
  for (CurveSegment& segment : times.segments) segment.type = SegmentType::kBezier;
  const Curve a = WithValues(rng, times);
  EXPECT_TRUE(SameCurveTimes(a, WithValues(rng, times)));  // values may differ
  const auto changed = [&](auto change) {
    Curve b = WithValues(rng, times);
    change(b);
    return !SameCurveTimes(a, b) && !SameCurveTimes(b, a);
  };
  EXPECT_TRUE(changed([](Curve& b) { b.start.frame += 0.5; }));
  EXPECT_TRUE(changed([](Curve& b) { b.segments[1].end.frame -= 1e-9; }));
  EXPECT_TRUE(changed([](Curve& b) {
    b.segments[1].handles[0].frame = std::nextafter(b.segments[1].handles[0].frame, 1e9);
  }));
  EXPECT_TRUE(changed([](Curve& b) {
    b.segments[2].handles[1].frame = std::nextafter(b.segments[2].handles[1].frame, -1e9);
  }));
  EXPECT_TRUE(changed([](Curve& b) { b.segments[0].type = SegmentType::kLinear; }));
  EXPECT_TRUE(changed([](Curve& b) { b.segments.pop_back(); }));
  EXPECT_TRUE(changed([](Curve& b) { b.samples.assign(10, 0.0); }));
  // A linear segment's handles are not its times.
  Curve linear = times;
  linear.segments[0].type = SegmentType::kLinear;
  Curve other = linear;
  other.segments[0].handles[0].frame += 0.25;
  EXPECT_TRUE(SameCurveTimes(linear, other));
}

}  // namespace
}  // namespace koma

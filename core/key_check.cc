// The key check: keyed extremes and ends of the input against the stepped curves written.
#include "core/key_check.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace koma {
namespace {

// A stepped curve's value at `time` (source frames): the last point at or before it (a hair of
// tolerance for times computed by another path), the first point's before them all.
double SteppedAt(const std::vector<CurvePoint>& steps, double time) {
  const double slack = 1e-9 * std::max(1.0, std::fabs(time));
  const auto after = std::upper_bound(
      steps.begin(), steps.end(), time + slack,
      [](double t, const CurvePoint& p) { return t < p.frame; });
  if (after == steps.begin()) return steps.front().value;
  return std::prev(after)->value;
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size()))) - 1;
  return values[std::min(index, values.size() - 1)];
}

}  // namespace

KeyCheck CheckKeys(const CurveSet& input, const std::vector<const std::vector<CurvePoint>*>& stepped,
                   const KeyCheckOptions& options) {
  KeyCheck check;
  // Timing frames: frame g lies at g * step source frames.
  const bool on_grid = options.timing_fps > 0.0 &&
                       std::fabs(options.timing_fps - input.fps) > 1e-4 * input.fps;
  const double step = on_grid ? input.fps / options.timing_fps : 1.0;
  const double last_source = static_cast<double>(input.frame_count - 1);
  const int last_frame = static_cast<int>(std::floor(last_source / step + 1e-9));
  check.seconds = last_frame * step / input.fps;
  std::vector<double> rates;
  for (size_t c = 0; c < input.curves.size(); ++c) {
    const Curve& curve = input.curves[c];
    const std::vector<CurvePoint>* out = c < stepped.size() ? stepped[c] : nullptr;
    if (out == nullptr || out->empty()) continue;
    // The keys: a dense curve's samples, else the keyframes (no inserted points).
    std::vector<CurvePoint> points;
    if (curve.dense()) {
      for (size_t f = 0; f < curve.samples.size(); ++f) {
        points.push_back({static_cast<double>(f), curve.samples[f]});
      }
    } else {
      points.push_back(curve.start);
      for (const CurveSegment& s : curve.segments) {
        if (!s.inserted) points.push_back(s.end);
      }
    }
    if (points.size() < 2) continue;
    double low = points[0].value, high = points[0].value;
    for (const CurvePoint& p : points) {
      low = std::min(low, p.value);
      high = std::max(high, p.value);
    }
    const double range = high - low;
    if (!(range > 0.0)) continue;  // a flat curve: nothing to miss
    CurveKeyCheck result;
    result.id = curve.id;
    const auto miss = [&](double drawn, double key) { return std::fabs(drawn - key) / range; };
    // What the input shows at key i's time (an inverse-stepped segment shows the value it
    // steps to from its first point on).
    const auto shown = [&](size_t i) {
      return EvaluateCurve(curve, points[i].frame, input.beziers_restricted);
    };
    // The timing frame nearest a source time (ties to the earlier), within the clip.
    const auto frame_of = [&](double time) {
      const double g = std::ceil(time / step - 0.5 - 1e-9);
      return static_cast<int>(std::clamp(g, 0.0, static_cast<double>(last_frame)));
    };
    for (size_t i = 1; i + 1 < points.size(); ++i) {
      const double in = points[i].value - points[i - 1].value;
      const double next = points[i + 1].value - points[i].value;
      const bool turns = (in > 0 && next < 0) || (in < 0 && next > 0);
      const bool hold_edge = (in == 0) != (next == 0);
      if (!turns && !hold_edge) continue;
      ++result.extremes;
      const int g = frame_of(points[i].frame);
      double best = HUGE_VAL;
      for (int k = std::max(0, g - options.window); k <= std::min(last_frame, g + options.window);
           ++k) {
        best = std::min(best, miss(SteppedAt(*out, k * step), shown(i)));
      }
      if (best > options.tolerance) {
        ++result.extremes_missed;
        if (best > result.worst_miss) {
          result.worst_miss = best;
          result.worst_miss_frame = points[i].frame;
        }
      }
    }
    result.first_missed = miss(out->front().value, shown(0)) > options.tolerance;
    result.last_missed = miss(out->back().value, shown(points.size() - 1)) > options.tolerance;
    double previous = SteppedAt(*out, 0.0);
    result.drawings = 1;
    for (int k = 1; k <= last_frame; ++k) {
      const double value = SteppedAt(*out, k * step);
      if (value != previous) ++result.drawings;
      previous = value;
    }
    check.extremes += result.extremes;
    check.extremes_missed += result.extremes_missed;
    check.ends_missed += (result.first_missed ? 1 : 0) + (result.last_missed ? 1 : 0);
    if (check.seconds > 0.0) rates.push_back(result.drawings / check.seconds);
    check.curves.push_back(std::move(result));
  }
  check.drawings_per_second_median = Quantile(rates, 0.5);
  check.drawings_per_second_p95 = Quantile(rates, 0.95);
  check.drawings_per_second_max = Quantile(rates, 1.0);
  return check;
}

}  // namespace koma

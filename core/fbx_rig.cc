#include "core/fbx_rig.h"

#include <algorithm>
#include <cmath>

#include "core/stop_check.h"

namespace koma {
namespace {

using Matrix = std::array<double, 16>;  // row-major 4x4, column vectors: p' = M p

constexpr double kPi = 3.14159265358979323846;

Matrix Identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Matrix Multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double sum = 0;
      for (int k = 0; k < 4; ++k) sum += a[r * 4 + k] * b[k * 4 + c];
      m[r * 4 + c] = sum;
    }
  }
  return m;
}

Matrix Translation(const std::array<double, 3>& t, double sign = 1.0) {
  Matrix m = Identity();
  m[3] = sign * t[0];
  m[7] = sign * t[1];
  m[11] = sign * t[2];
  return m;
}

Matrix Scaling(const std::array<double, 3>& s) {
  Matrix m = Identity();
  m[0] = s[0];
  m[5] = s[1];
  m[10] = s[2];
  return m;
}

Matrix AxisRotation(int axis, double degrees) {
  const double a = degrees * kPi / 180.0;
  const double c = std::cos(a);
  const double s = std::sin(a);
  Matrix m = Identity();
  const int i = (axis + 1) % 3;
  const int j = (axis + 2) % 3;
  m[i * 4 + i] = c;
  m[i * 4 + j] = -s;
  m[j * 4 + i] = s;
  m[j * 4 + j] = c;
  return m;
}

// The Euler rotation applying its axes in `order`, first to last.
Matrix EulerRotation(const std::array<double, 3>& degrees, FbxRotationOrder order) {
  static constexpr int kAxes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0},
                                      {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
  const int* axes = kAxes[static_cast<int>(order)];
  Matrix m = Identity();
  for (int k = 0; k < 3; ++k) m = Multiply(AxisRotation(axes[k], degrees[axes[k]]), m);
  return m;
}

// A rotation's inverse: its transpose.
Matrix Transposed(const Matrix& r) {
  Matrix m = r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i * 4 + j] = r[j * 4 + i];
  }
  return m;
}

double CubicValue(const FbxKeyCurve& curve, size_t k, int64_t tick) {
  const double dt = static_cast<double>(curve.times[k + 1] - curve.times[k]) /
                    static_cast<double>(kFbxTicksPerSecond);
  const double t =
      static_cast<double>(tick - curve.times[k]) / static_cast<double>(kFbxTicksPerSecond);
  const double v0 = curve.values[k];
  const double v1 = curve.values[k + 1];
  const double w0 = curve.right_weights[k];
  const double w1 = curve.next_left_weights[k];
  // The Bézier handles, in (time, value): a third of the segment when unweighted, where
  // this is the Hermite curve of the two slopes.
  const double x1 = w0 * dt, y1 = v0 + curve.right_slopes[k] * w0 * dt;
  const double x2 = dt - w1 * dt, y2 = v1 - curve.next_left_slopes[k] * w1 * dt;
  // The curve's parameter at time t: bisection on its time, which increases when the
  // weights are in [0, 1] (FBX keeps them there).
  double lo = 0.0, hi = 1.0, u = t / dt;
  for (int i = 0; i < 48; ++i) {
    const double m = 1.0 - u;
    const double x = 3 * m * m * u * x1 + 3 * m * u * u * x2 + u * u * u * dt;
    if (x < t) {
      lo = u;
    } else {
      hi = u;
    }
    u = 0.5 * (lo + hi);
  }
  const double m = 1.0 - u;
  return m * m * m * v0 + 3 * m * m * u * y1 + 3 * m * u * u * y2 + u * u * u * v1;
}

}  // namespace

double EvaluateFbxCurve(const FbxKeyCurve& curve, int64_t tick) {
  size_t cursor = 0;
  return EvaluateFbxCurveFrom(curve, tick, cursor);
}

double EvaluateFbxCurveFrom(const FbxKeyCurve& curve, int64_t tick, size_t& cursor) {
  if (curve.times.empty()) return 0.0;
  if (tick <= curve.times.front()) return curve.values.front();
  if (tick >= curve.times.back()) return curve.values.back();
  // The segment holding `tick`: from the cursor when the ticks come in order (a step or two),
  // else by bisection.
  size_t k = cursor < curve.times.size() - 1 ? cursor : 0;
  if (curve.times[k] > tick || curve.times[k + 1] <= tick) {
    if (k + 2 < curve.times.size() && curve.times[k + 1] <= tick && curve.times[k + 2] > tick) {
      ++k;
    } else {
      k = static_cast<size_t>(std::upper_bound(curve.times.begin(), curve.times.end(), tick) -
                              curve.times.begin() - 1);
    }
  }
  cursor = k;
  if (tick == curve.times[k]) return curve.values[k];  // on a key, as a baked take's frames are
  switch (curve.segments[k]) {
    case FbxKeyCurve::Segment::kConstant:
      return curve.values[k];
    case FbxKeyCurve::Segment::kConstantNext:
      return curve.values[k + 1];
    case FbxKeyCurve::Segment::kLinear: {
      const double s = static_cast<double>(tick - curve.times[k]) /
                       static_cast<double>(curve.times[k + 1] - curve.times[k]);
      return curve.values[k] + s * (curve.values[k + 1] - curve.values[k]);
    }
    case FbxKeyCurve::Segment::kCubic:
      return CubicValue(curve, k, tick);
  }
  return curve.values[k];
}

std::vector<double> FbxNodePositions(const FbxRig& rig, int64_t start_tick, double fps,
                                     int64_t frames) {
  const size_t n = rig.nodes.size();
  std::vector<double> positions(static_cast<size_t>(frames) * n * 3);
  std::vector<Matrix> world(n);
  // What does not change with time, per node: the pre and inverse post rotations, and the
  // offset and pivot translations on either side of R and S (skipped when zero, as they
  // mostly are).
  struct Fixed {
    Matrix pre, post, before_r, after_r, after_s;
    bool has_before_r, has_after_r, has_after_s;
  };
  const auto is_zero = [](const std::array<double, 3>& v) {
    return v[0] == 0 && v[1] == 0 && v[2] == 0;
  };
  std::vector<Fixed> fixed(n);
  for (size_t i = 0; i < n; ++i) {
    const FbxRigNode& node = rig.nodes[i];
    Fixed& f = fixed[i];
    f.pre = EulerRotation(node.pre_rotation, FbxRotationOrder::kXyz);
    f.post = Transposed(EulerRotation(node.post_rotation, FbxRotationOrder::kXyz));
    f.before_r = Multiply(Translation(node.rotation_offset), Translation(node.rotation_pivot));
    f.has_before_r = !is_zero(node.rotation_offset) || !is_zero(node.rotation_pivot);
    f.after_r =
        Multiply(Multiply(Translation(node.rotation_pivot, -1.0), Translation(node.scaling_offset)),
                 Translation(node.scaling_pivot));
    f.has_after_r = !is_zero(node.rotation_pivot) || !is_zero(node.scaling_offset) ||
                    !is_zero(node.scaling_pivot);
    f.after_s = Translation(node.scaling_pivot, -1.0);
    f.has_after_s = !is_zero(node.scaling_pivot);
  }
  std::vector<size_t> cursors(rig.curves.size(), 0);
  StopPoll stop(/*steps_between_checks=*/1 << 14);  // node transforms
  for (int64_t f = 0; f < frames; ++f) {
    if (stop.Stop(static_cast<int64_t>(n))) break;  // the caller asks StopReason()
    const int64_t tick = start_tick + std::llround(static_cast<double>(f) *
                                                   static_cast<double>(kFbxTicksPerSecond) / fps);
    for (size_t i = 0; i < n; ++i) {
      const FbxRigNode& node = rig.nodes[i];
      const Fixed& fix = fixed[i];
      const auto animated = [&](const std::array<double, 3>& rest,
                                const std::array<int, 3>& curves) {
        std::array<double, 3> value = rest;
        for (int a = 0; a < 3; ++a) {
          if (curves[a] >= 0) {
            const auto c = static_cast<size_t>(curves[a]);
            value[a] = EvaluateFbxCurveFrom(rig.curves[c], tick, cursors[c]);
          }
        }
        return value;
      };
      const Matrix r = EulerRotation(animated(node.rotation, node.rotation_curves), node.order);
      Matrix local = Translation(animated(node.translation, node.translation_curves));
      if (fix.has_before_r) local = Multiply(local, fix.before_r);
      local = Multiply(local, Multiply(fix.pre, Multiply(r, fix.post)));
      if (fix.has_after_r) local = Multiply(local, fix.after_r);
      local = Multiply(local, Scaling(animated(node.scaling, node.scaling_curves)));
      if (fix.has_after_s) local = Multiply(local, fix.after_s);
      world[i] = node.parent < 0 ? local : Multiply(world[static_cast<size_t>(node.parent)], local);
      double* out = positions.data() + (static_cast<size_t>(f) * n + i) * 3;
      out[0] = world[i][3];
      out[1] = world[i][7];
      out[2] = world[i][11];
    }
  }
  return positions;
}

}  // namespace koma

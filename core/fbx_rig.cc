#include "core/fbx_rig.h"

#include <algorithm>
#include <cmath>

#include "core/stop_check.h"

namespace koma {
namespace {

using Matrix = std::array<double, 16>;  // row-major 4x4, column vectors: p' = M p

constexpr double kPi = 3.14159265358979323846;

Matrix Identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

// Every matrix here is affine (its last row 0 0 0 1), so the product's is too: 36
// multiplications, not 64.
Matrix Multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int r = 0; r < 3; ++r) {
    const double* row = &a[static_cast<size_t>(r) * 4];
    for (int c = 0; c < 4; ++c) {
      m[r * 4 + c] = row[0] * b[c] + row[1] * b[4 + c] + row[2] * b[8 + c];
    }
    m[r * 4 + 3] += row[3];
  }
  m[15] = 1.0;
  return m;
}

Matrix Translation(const std::array<double, 3>& t, double sign = 1.0) {
  Matrix m = Identity();
  m[3] = sign * t[0];
  m[7] = sign * t[1];
  m[11] = sign * t[2];
  return m;
}

// The Euler rotation applying its axes in `order`, first to last.
Matrix EulerRotation(const std::array<double, 3>& degrees, FbxRotationOrder order) {
  static constexpr int kAxes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0},
                                      {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
  const int* axes = kAxes[static_cast<int>(order)];
  Matrix m = Identity();
  for (int k = 0; k < 3; ++k) {
    // m = AxisRotation(axis) * m, which mixes only two of m's rows.
    const double a = degrees[axes[k]] * kPi / 180.0;
    const double c = std::cos(a);
    const double s = std::sin(a);
    double* row_i = &m[static_cast<size_t>((axes[k] + 1) % 3) * 4];
    double* row_j = &m[static_cast<size_t>((axes[k] + 2) % 3) * 4];
    for (int col = 0; col < 3; ++col) {
      const double x = row_i[col], y = row_j[col];
      row_i[col] = c * x - s * y;
      row_j[col] = s * x + c * y;
    }
  }
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
  // The curve's parameter at time t, where its time x(u) reaches t: Newton's steps from the
  // unweighted answer t / dt (exact when both weights are 1/3, where x is linear in u), kept
  // inside a bracket that bisection narrows when a step leaves it. x increases with u when
  // the weights are in [0, 1] (FBX keeps them there).
  const auto time_at = [&](double u) {
    const double m = 1.0 - u;
    return 3 * m * m * u * x1 + 3 * m * u * u * x2 + u * u * u * dt;
  };
  const auto slope_at = [&](double u) {  // dx/du
    const double m = 1.0 - u;
    return 3 * m * m * x1 + 6 * m * u * (x2 - x1) + 3 * u * u * (dt - x2);
  };
  double lo = 0.0, hi = 1.0, u = std::clamp(t / dt, 0.0, 1.0);
  for (int i = 0; i < 64; ++i) {
    const double error = time_at(u) - t;
    if (std::fabs(error) <= 1e-15 * dt) break;
    if (error < 0) {
      lo = u;
    } else {
      hi = u;
    }
    const double slope = slope_at(u);
    const double step = slope > 0 ? u - error / slope : -1.0;
    u = step > lo && step < hi ? step : 0.5 * (lo + hi);
    if (hi - lo <= 1e-16) break;
  }
  const double m = 1.0 - u;
  return m * m * m * v0 + 3 * m * m * u * y1 + 3 * m * u * u * y2 + u * u * u * v1;
}

// The 3x3 part's inverse (the translation left zero); false when it is singular.
bool InverseLinear(const Matrix& m, Matrix& inverse) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
               k = m[10];
  const double det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g);
  if (!(std::fabs(det) > 1e-300)) return false;
  inverse = {(e * k - f * h) / det,
             (c * h - b * k) / det,
             (b * f - c * e) / det,
             0,
             (f * g - d * k) / det,
             (a * k - c * g) / det,
             (c * d - a * f) / det,
             0,
             (d * h - e * g) / det,
             (b * g - a * h) / det,
             (a * e - b * d) / det,
             0,
             0,
             0,
             0,
             1};
  return true;
}

// A node's world transform when its InheritType is not RSrs (where it is simply
// parent_world * local), as the FBX SDK's transformation sample composes it:
//   linear = ParentR * (Rpre R Rpost^-1) * ParentSS * S     (RrSs)
//   linear = ParentR * (Rpre R Rpost^-1) * ParentSS * ParentS^-1 * S     (Rrs)
// with ParentR the parent's world rotation (its linear part's columns normalised, as
// three.js's FBXLoader takes it), ParentSS = ParentR^-1 * the parent's linear part (its
// shear and scale) and ParentS the parent's own Lcl Scaling; the translation is the local
// chain's, placed by the parent's whole world transform in every type. A degenerate parent
// (a zero scale) is inherited as RSrs.
Matrix InheritedWorld(const Matrix& parent_world, const std::array<double, 3>& parent_scale,
                      const Matrix& local, const Matrix& rotation,
                      const std::array<double, 3>& scale, FbxInheritType type) {
  const Matrix simple = Multiply(parent_world, local);
  Matrix parent_rotation = Identity();
  for (int col = 0; col < 3; ++col) {
    const double length = std::hypot(parent_world[static_cast<size_t>(col)],
                                     parent_world[static_cast<size_t>(4 + col)],
                                     parent_world[static_cast<size_t>(8 + col)]);
    if (!(length > 0)) return simple;
    for (int row = 0; row < 3; ++row) {
      parent_rotation[static_cast<size_t>(row * 4 + col)] =
          parent_world[static_cast<size_t>(row * 4 + col)] / length;
    }
  }
  Matrix parent_linear = parent_world;
  parent_linear[3] = parent_linear[7] = parent_linear[11] = 0;
  Matrix rotation_inverse;
  if (!InverseLinear(parent_rotation, rotation_inverse)) return simple;
  Matrix shear_scale = Multiply(rotation_inverse, parent_linear);
  if (type == FbxInheritType::kRrs) {
    for (int col = 0; col < 3; ++col) {
      if (parent_scale[static_cast<size_t>(col)] == 0) return simple;
      for (int row = 0; row < 3; ++row) {
        shear_scale[static_cast<size_t>(row * 4 + col)] /= parent_scale[static_cast<size_t>(col)];
      }
    }
  }
  Matrix world = Multiply(Multiply(parent_rotation, rotation), shear_scale);
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) world[static_cast<size_t>(row * 4 + col)] *= scale[col];
  }
  world[3] = simple[3];
  world[7] = simple[7];
  world[11] = simple[11];
  return world;
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
  // The segment holding `tick` (times[k] <= tick < times[k + 1], which exists: tick is inside
  // the keys): from the cursor when the ticks come in order, a few steps on (a take's frames
  // and its keys are seldom on exactly the same ticks: a key a tick late puts the next frame
  // two keys on); else by bisection.
  const auto after = [&](size_t from) {
    return static_cast<size_t>(
        std::upper_bound(curve.times.begin() + static_cast<std::ptrdiff_t>(from), curve.times.end(),
                         tick) -
        curve.times.begin() - 1);
  };
  size_t k = cursor < curve.times.size() - 1 ? cursor : 0;
  if (curve.times[k] > tick) {
    k = after(0);
  } else {
    for (int step = 0; step < 8 && curve.times[k + 1] <= tick; ++step) ++k;
    if (curve.times[k + 1] <= tick) k = after(k);
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
  std::vector<std::array<double, 3>> scales(n);  // each node's Lcl Scaling at this frame
  // What does not change with time, per node: the pre and inverse post rotations, and the
  // offset and pivot translations on either side of R and S (skipped when zero, as they
  // mostly are).
  struct Fixed {
    Matrix pre, post, before_r, after_r, after_s;
    bool has_pre, has_post, has_before_r, has_after_r, has_after_s;
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
    f.has_pre = !is_zero(node.pre_rotation);
    f.has_post = !is_zero(node.post_rotation);
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
  // The curves are evaluated a block of frames at a time, one curve after another (each
  // curve's keys read in order: a take's hundreds of curves, read frame by frame, missed the
  // cache at every key), then the block's transforms frame by frame.
  constexpr int64_t kBlock = 64;  // frames
  const size_t curves = rig.curves.size();
  std::vector<double> block(curves * kBlock);  // curve-major: block[c * kBlock + j]
  std::vector<int64_t> ticks(kBlock);
  std::vector<size_t> cursors(curves, 0);
  StopPoll stop(/*steps_between_checks=*/1 << 14);  // node transforms
  for (int64_t first = 0; first < frames; first += kBlock) {
    if (stop.Stop(static_cast<int64_t>(n) * kBlock)) break;  // the caller asks StopReason()
    const int64_t count = std::min(kBlock, frames - first);
    for (int64_t j = 0; j < count; ++j) {
      ticks[static_cast<size_t>(j)] =
          start_tick + std::llround(static_cast<double>(first + j) *
                                    static_cast<double>(kFbxTicksPerSecond) / fps);
    }
    for (size_t c = 0; c < curves; ++c) {
      double* values = block.data() + c * kBlock;
      for (int64_t j = 0; j < count; ++j) {
        values[j] = EvaluateFbxCurveFrom(rig.curves[c], ticks[static_cast<size_t>(j)], cursors[c]);
      }
    }
    for (int64_t j = 0; j < count; ++j) {
      const int64_t f = first + j;
      for (size_t i = 0; i < n; ++i) {
        const FbxRigNode& node = rig.nodes[i];
        const Fixed& fix = fixed[i];
        const auto animated = [&](const std::array<double, 3>& rest,
                                  const std::array<int, 3>& channel_curves) {
          std::array<double, 3> value = rest;
          for (int a = 0; a < 3; ++a) {
            if (channel_curves[a] >= 0) {
              value[a] =
                  block[static_cast<size_t>(channel_curves[a]) * kBlock + static_cast<size_t>(j)];
            }
          }
          return value;
        };
        // local = T * Roff * Rp * Rpre * R * Rpost^-1 * Rp^-1 * Soff * Sp * S * Sp^-1, built
        // from the middle out, the factors that are identity skipped; S scales columns and T
        // adds to the last one.
        Matrix rotation = EulerRotation(animated(node.rotation, node.rotation_curves), node.order);
        if (fix.has_pre) rotation = Multiply(fix.pre, rotation);
        if (fix.has_post) rotation = Multiply(rotation, fix.post);
        Matrix local = fix.has_before_r ? Multiply(fix.before_r, rotation) : rotation;
        if (fix.has_after_r) local = Multiply(local, fix.after_r);
        const std::array<double, 3> scale = animated(node.scaling, node.scaling_curves);
        for (int row = 0; row < 3; ++row) {
          for (int col = 0; col < 3; ++col) local[static_cast<size_t>(row * 4 + col)] *= scale[col];
        }
        if (fix.has_after_s) local = Multiply(local, fix.after_s);
        const std::array<double, 3> t = animated(node.translation, node.translation_curves);
        local[3] += t[0];
        local[7] += t[1];
        local[11] += t[2];
        scales[i] = scale;
        if (node.parent < 0) {
          world[i] = local;
        } else if (node.inherit == FbxInheritType::kRSrs) {
          world[i] = Multiply(world[static_cast<size_t>(node.parent)], local);
        } else {
          const auto parent = static_cast<size_t>(node.parent);
          world[i] =
              InheritedWorld(world[parent], scales[parent], local, rotation, scale, node.inherit);
        }
        double* out = positions.data() + (static_cast<size_t>(f) * n + i) * 3;
        out[0] = world[i][3];
        out[1] = world[i][7];
        out[2] = world[i][11];
      }
    }
  }
  return positions;
}

}  // namespace koma

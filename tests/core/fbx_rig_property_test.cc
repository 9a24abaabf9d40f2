// Property tests of core/fbx_rig: the fast evaluation (curves a block of frames at a time
// with a cursor, Newton's steps on cubic segments, affine products with identity factors
// skipped) against a naive reference written straight from the definitions (a fresh search
// per key, bisection, full 4x4 products of every factor of the documented chain), on random
// rigs and curves.
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/fbx_rig.h"
#include "gtest/gtest.h"

namespace koma {
namespace {

using Matrix = std::array<double, 16>;  // row-major, column vectors

Matrix Identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Matrix Product(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      for (int k = 0; k < 4; ++k) m[r * 4 + c] += a[r * 4 + k] * b[k * 4 + c];
    }
  }
  return m;
}

Matrix Translate(const std::array<double, 3>& t, double sign = 1) {
  Matrix m = Identity();
  m[3] = sign * t[0];
  m[7] = sign * t[1];
  m[11] = sign * t[2];
  return m;
}

Matrix Scale(const std::array<double, 3>& s) {
  Matrix m = Identity();
  m[0] = s[0];
  m[5] = s[1];
  m[10] = s[2];
  return m;
}

Matrix Rotate(int axis, double degrees) {
  const double a = degrees * M_PI / 180;
  Matrix m = Identity();
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  m[i * 4 + i] = std::cos(a);
  m[i * 4 + j] = -std::sin(a);
  m[j * 4 + i] = std::sin(a);
  m[j * 4 + j] = std::cos(a);
  return m;
}

Matrix Euler(const std::array<double, 3>& d, int order) {
  static constexpr int kAxes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0},
                                      {1, 0, 2}, {2, 0, 1}, {2, 1, 0}};
  Matrix m = Identity();
  for (int axis : kAxes[order]) m = Product(Rotate(axis, d[axis]), m);
  return m;
}

Matrix Transpose(const Matrix& r) {
  Matrix m = r;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[i * 4 + j] = r[j * 4 + i];
  }
  return m;
}

// The inverse of an affine matrix by Gauss-Jordan elimination with partial pivoting.
Matrix Inverse(Matrix m) {
  Matrix inv = Identity();
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r) {
      if (std::fabs(m[r * 4 + col]) > std::fabs(m[pivot * 4 + col])) pivot = r;
    }
    for (int c = 0; c < 4; ++c) {
      std::swap(m[col * 4 + c], m[pivot * 4 + c]);
      std::swap(inv[col * 4 + c], inv[pivot * 4 + c]);
    }
    const double d = m[col * 4 + col];
    for (int c = 0; c < 4; ++c) {
      m[col * 4 + c] /= d;
      inv[col * 4 + c] /= d;
    }
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = m[r * 4 + col];
      for (int c = 0; c < 4; ++c) {
        m[r * 4 + c] -= f * m[col * 4 + c];
        inv[r * 4 + c] -= f * inv[col * 4 + c];
      }
    }
  }
  return inv;
}

// The world transform of a node inheriting RrSs or Rrs, step by step as the FBX SDK's
// transformations sample composes it: the parent's rotation (its columns normalised), its
// shear-and-scale ParentR^-1 * (ParentT^-1 * ParentWorld), the global rotation-scale of the
// inherit type, the translation the local chain gives placed by the parent's world.
Matrix SdkSampleWorld(const Matrix& parent_world, const std::array<double, 3>& parent_scale,
                      const Matrix& local, const Matrix& pre, const Matrix& r, const Matrix& post,
                      const std::array<double, 3>& scale, FbxInheritType type) {
  Matrix parent_r = Identity();
  for (int c = 0; c < 3; ++c) {
    const double length =
        std::sqrt(parent_world[c] * parent_world[c] + parent_world[4 + c] * parent_world[4 + c] +
                  parent_world[8 + c] * parent_world[8 + c]);
    for (int row = 0; row < 3; ++row) parent_r[row * 4 + c] = parent_world[row * 4 + c] / length;
  }
  Matrix parent_t = Identity();
  for (int row = 0; row < 3; ++row) parent_t[row * 4 + 3] = parent_world[row * 4 + 3];
  const Matrix parent_rs = Product(Inverse(parent_t), parent_world);
  Matrix parent_s = Product(Inverse(parent_r), parent_rs);
  if (type == FbxInheritType::kRrs) parent_s = Product(parent_s, Inverse(Scale(parent_scale)));
  const Matrix global_rs =
      Product(Product(Product(parent_r, Product(Product(pre, r), post)), parent_s), Scale(scale));
  const Matrix global_t =
      Translate({Product(parent_world, local)[3], Product(parent_world, local)[7],
                 Product(parent_world, local)[11]});
  return Product(global_t, global_rs);
}

// The curve's value by its definition: the segment by a linear scan, a cubic's parameter by
// bisection to the last bit.
double NaiveValue(const FbxKeyCurve& c, int64_t tick) {
  if (tick <= c.times.front()) return c.values.front();
  if (tick >= c.times.back()) return c.values.back();
  size_t k = 0;
  while (c.times[k + 1] <= tick) ++k;
  const double s = double(tick - c.times[k]) / double(c.times[k + 1] - c.times[k]);
  switch (c.segments[k]) {
    case FbxKeyCurve::Segment::kConstant:
      return c.values[k];
    case FbxKeyCurve::Segment::kConstantNext:
      return c.values[k + 1];
    case FbxKeyCurve::Segment::kLinear:
      return c.values[k] + s * (c.values[k + 1] - c.values[k]);
    case FbxKeyCurve::Segment::kCubic:
      break;
  }
  const double dt = double(c.times[k + 1] - c.times[k]) / kFbxTicksPerSecond;
  const double x1 = c.right_weights[k], x2 = 1 - c.next_left_weights[k];  // in segments
  const double y1 = c.values[k] + c.right_slopes[k] * c.right_weights[k] * dt;
  const double y2 = c.values[k + 1] - c.next_left_slopes[k] * c.next_left_weights[k] * dt;
  double lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const double u = (lo + hi) / 2, m = 1 - u;
    (3 * m * m * u * x1 + 3 * m * u * u * x2 + u * u * u < s ? lo : hi) = u;
  }
  const double u = (lo + hi) / 2, m = 1 - u;
  return m * m * m * c.values[k] + 3 * m * m * u * y1 + 3 * m * u * u * y2 +
         u * u * u * c.values[k + 1];
}

FbxKeyCurve RandomCurve(std::mt19937_64& random, int64_t span) {
  std::uniform_real_distribution<double> value(-90, 90), unit(0, 1);
  FbxKeyCurve c;
  const int keys = 2 + int(random() % 12);
  int64_t t = int64_t(random() % 1000) - 500;
  for (int k = 0; k < keys; ++k) {
    t += 1 + int64_t(unit(random) * double(span) / keys);
    c.times.push_back(t);
    c.values.push_back(value(random));
  }
  const bool any_cubic = unit(random) < 0.7;
  for (int k = 0; k < keys; ++k) {
    const double kind = unit(random);
    c.segments.push_back(!any_cubic || kind < 0.2 ? FbxKeyCurve::Segment::kLinear
                         : kind < 0.3             ? FbxKeyCurve::Segment::kConstant
                         : kind < 0.35            ? FbxKeyCurve::Segment::kConstantNext
                                                  : FbxKeyCurve::Segment::kCubic);
    if (!any_cubic) continue;
    c.right_slopes.push_back(value(random) * 10);
    c.next_left_slopes.push_back(value(random) * 10);
    // Unweighted (1/3), the SDK's 0.3333, or any weight in [0, 1].
    const double w = unit(random);
    c.right_weights.push_back(w < 0.3 ? 1.0 / 3 : w < 0.5 ? 0.3333 : unit(random));
    c.next_left_weights.push_back(w < 0.3 ? 1.0 / 3 : w < 0.5 ? 0.3333 : unit(random));
  }
  return c;
}

TEST(FbxRigPropertyTest, CurvesEqualTheirDefinitionInAnyTickOrder) {
  std::mt19937_64 random(43);
  for (int trial = 0; trial < 300; ++trial) {
    const int64_t span = kFbxTicksPerSecond * (1 + trial % 5);
    const FbxKeyCurve curve = RandomCurve(random, span);
    size_t cursor = 0;
    int64_t tick = curve.times.front() - 1000;
    for (int q = 0; q < 400; ++q) {
      // Mostly forward in small steps (a take's frames, holds), sometimes a jump either way.
      const uint64_t how = random() % 10;
      tick += how < 6   ? int64_t(random() % uint64_t(span / 60))
              : how < 8 ? 0
                        : int64_t(random() % uint64_t(span)) - span / 2;
      const double expected = NaiveValue(curve, tick);
      const double scale = 1 + std::fabs(expected);
      ASSERT_NEAR(EvaluateFbxCurveFrom(curve, tick, cursor), expected, 1e-9 * scale)
          << "trial " << trial << " query " << q << " tick " << tick;
      ASSERT_NEAR(EvaluateFbxCurve(curve, tick), expected, 1e-9 * scale);
    }
  }
}

TEST(FbxRigPropertyTest, PositionsEqualTheDocumentedChainOfFullProducts) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-20, 20), angle(-180, 180), unit(0, 1);
  const auto vector = [&](double probability, double lo, double hi) {
    std::array<double, 3> v{};
    if (unit(random) < probability) {
      for (double& x : v) x = lo + (hi - lo) * unit(random);
    }
    return v;
  };
  for (int trial = 0; trial < 40; ++trial) {
    FbxRig rig;
    const int nodes = 1 + int(random() % 12);
    const double fps = trial % 3 == 0 ? 30000.0 / 1001 : trial % 3 == 1 ? 24 : 120;
    const int64_t frames = 1 + int64_t(random() % 150);  // over two blocks of 64, and less
    const int64_t span = int64_t(double(frames) / fps * kFbxTicksPerSecond);
    for (int i = 0; i < nodes; ++i) {
      FbxRigNode n;
      n.parent = i == 0 ? -1 : int(random() % uint64_t(i + 1)) - 1;
      n.translation = vector(0.9, -20, 20);
      n.rotation = vector(0.8, -180, 180);
      n.scaling = {1, 1, 1};
      if (unit(random) < 0.3) n.scaling = vector(1, 0.5, 2);
      n.pre_rotation = vector(0.4, -180, 180);
      n.post_rotation = vector(0.3, -180, 180);
      n.rotation_offset = vector(0.3, -5, 5);
      n.rotation_pivot = vector(0.3, -5, 5);
      n.scaling_offset = vector(0.3, -5, 5);
      n.scaling_pivot = vector(0.3, -5, 5);
      n.order = static_cast<FbxRotationOrder>(random() % 6);
      n.inherit = static_cast<FbxInheritType>(random() % 3);
      for (std::array<int, 3>* channel :
           {&n.translation_curves, &n.rotation_curves, &n.scaling_curves}) {
        for (int& curve : *channel) {
          if (unit(random) < 0.5) continue;
          curve = int(rig.curves.size());
          FbxKeyCurve c = RandomCurve(random, span);
          if (channel == &n.scaling_curves) {
            for (double& v : c.values) v = 0.5 + std::fabs(v) / 90;
            for (double& s : c.right_slopes) s = 0;
            for (double& s : c.next_left_slopes) s = 0;
          }
          rig.curves.push_back(std::move(c));
        }
      }
      rig.nodes.push_back(n);
    }
    const int64_t start = int64_t(random() % 1000) - 500;
    const std::vector<double> fast = FbxNodePositions(rig, start, fps, frames);
    ASSERT_EQ(fast.size(), size_t(frames * nodes * 3));
    for (int64_t f = 0; f < frames; ++f) {
      const int64_t tick = start + std::llround(double(f) * double(kFbxTicksPerSecond) / fps);
      std::vector<Matrix> world(static_cast<size_t>(nodes));
      std::vector<std::array<double, 3>> scales(static_cast<size_t>(nodes));
      for (int i = 0; i < nodes; ++i) {
        const FbxRigNode& n = rig.nodes[size_t(i)];
        const auto at = [&](std::array<double, 3> v, const std::array<int, 3>& curves) {
          for (int a = 0; a < 3; ++a) {
            if (curves[a] >= 0) v[a] = NaiveValue(rig.curves[size_t(curves[a])], tick);
          }
          return v;
        };
        Matrix local = Identity();
        for (const Matrix& factor :
             {Translate(at(n.translation, n.translation_curves)), Translate(n.rotation_offset),
              Translate(n.rotation_pivot), Euler(n.pre_rotation, 0),
              Euler(at(n.rotation, n.rotation_curves), int(n.order)),
              Transpose(Euler(n.post_rotation, 0)), Translate(n.rotation_pivot, -1),
              Translate(n.scaling_offset), Translate(n.scaling_pivot),
              Scale(at(n.scaling, n.scaling_curves)), Translate(n.scaling_pivot, -1)}) {
          local = Product(local, factor);
        }
        scales[size_t(i)] = at(n.scaling, n.scaling_curves);
        world[size_t(i)] =
            n.parent < 0 || n.inherit == FbxInheritType::kRSrs
                ? (n.parent < 0 ? local : Product(world[size_t(n.parent)], local))
                : SdkSampleWorld(world[size_t(n.parent)], scales[size_t(n.parent)], local,
                                 Euler(n.pre_rotation, 0),
                                 Euler(at(n.rotation, n.rotation_curves), int(n.order)),
                                 Transpose(Euler(n.post_rotation, 0)), scales[size_t(i)],
                                 n.inherit);
        for (int a = 0; a < 3; ++a) {
          ASSERT_NEAR(fast[size_t((f * nodes + i) * 3 + a)], world[size_t(i)][size_t(a * 4 + 3)],
                      1e-7)
              << "trial " << trial << " frame " << f << " node " << i << " axis " << a;
        }
      }
    }
  }
}

}  // namespace
}  // namespace koma

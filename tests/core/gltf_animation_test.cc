// glTF animation evaluation (core/gltf_animation.h): hand-worked cases, then random samplers
// and hierarchies against an independent reference written from the glTF 2.0 specification's
// Appendix C with libm (std::acos, std::sin), a linear key search and 4x4 matrices built by
// rotating the basis vectors with q v q*.
#include "core/gltf_animation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "core/split_mix64.h"

namespace koma {
namespace {

using ::testing::DoubleNear;
using ::testing::ElementsAre;
using Quat = std::array<double, 4>;

constexpr double kPi = 3.14159265358979323846;

std::vector<double> Eval(const GltfSampler& sampler, bool rotation, double time,
                         double snap = 0) {
  std::vector<double> out(static_cast<size_t>(sampler.width));
  EvaluateGltfSampler(sampler, rotation, time, snap, out.data());
  return out;
}

Quat AxisAngle(double x, double y, double z, double degrees) {
  const double half = degrees * kPi / 360;
  const double s = std::sin(half) / std::sqrt(x * x + y * y + z * z);
  return {x * s, y * s, z * s, std::cos(half)};
}

TEST(GltfAnimationTest, LinearStepAndClamping) {
  GltfSampler s;
  s.times = {1, 2, 4};
  s.values = {0, 0, 0, 10, 20, 30, 30, 20, 10};
  EXPECT_THAT(Eval(s, false, 0.5), ElementsAre(0, 0, 0));     // before the first key
  EXPECT_THAT(Eval(s, false, 1.5), ElementsAre(5, 10, 15));   // halfway
  EXPECT_THAT(Eval(s, false, 3), ElementsAre(20, 20, 20));    // halfway of a 2 s interval
  EXPECT_THAT(Eval(s, false, 9), ElementsAre(30, 20, 10));    // after the last
  s.interpolation = GltfInterpolation::kStep;
  EXPECT_THAT(Eval(s, false, 1.99), ElementsAre(0, 0, 0));
  EXPECT_THAT(Eval(s, false, 2), ElementsAre(10, 20, 30));
  EXPECT_THAT(Eval(s, false, 3.99), ElementsAre(10, 20, 30));
}

TEST(GltfAnimationTest, SnapTakesTheKeyAFloatStored) {
  GltfSampler s;
  s.interpolation = GltfInterpolation::kStep;
  s.times = {0, static_cast<double>(1.0f / 24)};  // 0.041666668 s, just after 1/24
  s.width = 1;
  s.values = {0, 1};
  EXPECT_THAT(Eval(s, false, 1.0 / 24), ElementsAre(0));  // the spec, strictly: still key 0
  EXPECT_THAT(Eval(s, false, 1.0 / 24, GltfSnapSeconds(1.0 / 24, 24)), ElementsAre(1));
}

TEST(GltfAnimationTest, ZeroLengthIntervalJumpsToTheLaterKey) {
  GltfSampler s;
  s.width = 1;
  s.times = {0, 1, 1, 2};
  s.values = {0, 10, 100, 200};
  EXPECT_THAT(Eval(s, false, 0.5), ElementsAre(5));
  EXPECT_THAT(Eval(s, false, 1), ElementsAre(100));
  EXPECT_THAT(Eval(s, false, 1.5), ElementsAre(150));
  s.times = {0, 0, 1};  // at the very start too
  s.values = {7, 0, 10};
  EXPECT_THAT(Eval(s, false, 0), ElementsAre(0));
}

TEST(GltfAnimationTest, SlerpTakesTheShorterArc) {
  const Quat a = AxisAngle(0, 0, 1, 0);
  const Quat b = AxisAngle(0, 0, 1, 90);
  const Quat half = AxisAngle(0, 0, 1, 45);
  const Quat mid = GltfSlerp(a, b, 0.5);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(mid[i], half[i], 1e-15);
  // -b is the same rotation: the result is the same (up to the sign of q, here +).
  const Quat flipped = GltfSlerp(a, {-b[0], -b[1], -b[2], -b[3]}, 0.5);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(flipped[i], half[i], 1e-15);
  // A third of the way between 10 and 170 degrees about x.
  const Quat third = GltfSlerp(AxisAngle(1, 0, 0, 10), AxisAngle(1, 0, 0, 170), 1.0 / 3);
  const Quat expected = AxisAngle(1, 0, 0, 10 + 160.0 / 3);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(third[i], expected[i], 1e-14);
}

TEST(GltfAnimationTest, CubicSplineFollowsTheSpecFormula) {
  // One component: v0 = 0, b0 = 3 (out-tangent), v1 = 1, a1 = -1 (in-tangent), td = 2.
  GltfSampler s;
  s.interpolation = GltfInterpolation::kCubicSpline;
  s.width = 1;
  s.times = {0, 2};
  s.values = {99, 0, 3, -1, 1, 99};  // in, value, out per key
  // t = 0.5: h00 = 0.5, h10 = 2 * 0.125, h01 = 0.5, h11 = 2 * -0.125.
  EXPECT_THAT(Eval(s, false, 1), ElementsAre(DoubleNear(0.5 * 0 + 0.25 * 3 + 0.5 * 1 + -0.25 * -1,
                                                       1e-15)));
  EXPECT_THAT(Eval(s, false, 2), ElementsAre(1));
}

TEST(GltfAnimationTest, AcosDegreesMatchesLibm) {
  for (int i = 0; i <= 10000; ++i) {
    const double d = i / 10000.0;
    EXPECT_NEAR(AcosDegrees(d), std::acos(d) * 180 / kPi, 1e-11) << d;
  }
}

TEST(GltfAnimationTest, SourceRateFromTheKeys) {
  auto clip_with_spacing = [](double spacing, int keys) {
    GltfClip clip;
    GltfSampler s;
    for (int k = 0; k < keys; ++k) s.times.push_back(static_cast<float>(k * spacing));
    clip.samplers.push_back(s);
    return clip;
  };
  EXPECT_EQ(GltfAutoSourceFps(clip_with_spacing(1.0 / 24, 50)), 24);
  EXPECT_EQ(GltfAutoSourceFps(clip_with_spacing(1.0 / 60, 50)), 60);
  EXPECT_EQ(GltfAutoSourceFps(clip_with_spacing(0.5, 9)), 30);  // a pose every 0.5 s
  EXPECT_EQ(GltfAutoSourceFps(GltfClip{}), 30);
  const GltfClip clip = clip_with_spacing(1.0 / 24, 130);
  EXPECT_EQ(GltfFrameCount(clip, 24), 130);
  EXPECT_EQ(GltfFrameCount(clip, 30), 163);  // 5.375 s x 30 = 161.25: one frame past the end
  EXPECT_EQ(GltfFrameCount(clip_with_spacing(0.5, 9), 30), 121);
}

// ---- the independent reference ----

// `snap`: a time within snap of a key is that key (the latest such key), as documented.
std::vector<double> ReferenceEval(const GltfSampler& s, bool rotation, double tc, double snap = 0) {
  const size_t w = static_cast<size_t>(s.width);
  const bool cubic = s.interpolation == GltfInterpolation::kCubicSpline;
  auto value = [&](size_t k) {
    const size_t at = cubic ? (3 * k + 1) * w : k * w;
    return std::vector<double>(s.values.begin() + at, s.values.begin() + at + w);
  };
  const size_t n = s.times.size();
  for (size_t i = n; i-- > 0;) {
    if (snap > 0 && s.times[i] <= tc + snap) {
      if (s.times[i] >= tc - snap) return value(i);
      break;
    }
  }
  // The last key at or before tc (linear scan), the later one of equal keys.
  size_t k = 0;
  bool before_all = tc < s.times[0];
  for (size_t i = 0; i < n; ++i) {
    if (s.times[i] <= tc) k = i;
  }
  if (before_all) {
    return value(0);
  }
  if (k == n - 1 || s.interpolation == GltfInterpolation::kStep || s.times[k] == tc) return value(k);
  const double td = s.times[k + 1] - s.times[k];
  const double t = (tc - s.times[k]) / td;
  const std::vector<double> v0 = value(k), v1 = value(k + 1);
  std::vector<double> out(w);
  if (s.interpolation == GltfInterpolation::kLinear && rotation) {
    double dot = 0;
    for (size_t i = 0; i < 4; ++i) dot += v0[i] * v1[i];
    const double sign = dot < 0 ? -1 : 1;
    const double a = std::acos(std::min(1.0, std::fabs(dot)));
    if (std::fabs(dot) > 0.9995) {
      double len = 0;
      for (size_t i = 0; i < 4; ++i) {
        out[i] = (1 - t) * v0[i] + sign * t * v1[i];
        len += out[i] * out[i];
      }
      for (double& x : out) x /= std::sqrt(len);
      return out;
    }
    for (size_t i = 0; i < 4; ++i) {
      out[i] = std::sin(a * (1 - t)) / std::sin(a) * v0[i] + sign * std::sin(a * t) / std::sin(a) * v1[i];
    }
    return out;
  }
  if (s.interpolation == GltfInterpolation::kLinear) {
    for (size_t i = 0; i < w; ++i) out[i] = v0[i] + t * (v1[i] - v0[i]);
    return out;
  }
  // Hermite in matrix form: [t^3 t^2 t 1] M [v0 m0 v1 m1]^T.
  const double b0 = 2 * t * t * t - 3 * t * t + 1, b1 = t * t * t - 2 * t * t + t;
  const double b2 = -2 * t * t * t + 3 * t * t, b3 = t * t * t - t * t;
  const size_t out_tangent = (3 * k + 2) * w, in_tangent = (3 * (k + 1)) * w;
  double len = 0;
  for (size_t i = 0; i < w; ++i) {
    out[i] = b0 * v0[i] + b1 * td * s.values[out_tangent + i] + b2 * v1[i] +
             b3 * td * s.values[in_tangent + i];
    len += out[i] * out[i];
  }
  if (rotation) {
    for (double& x : out) x /= std::sqrt(len);
  }
  return out;
}

Quat RandomQuat(SplitMix64& rng) {
  Quat q;
  double len = 0;
  for (double& x : q) {
    x = rng.Unit() * 2 - 1;
    len += x * x;
  }
  for (double& x : q) x /= std::sqrt(len);
  if (rng.Unit() < 0.5) {  // a sign flip: the same rotation
    for (double& x : q) x = -x;
  }
  return q;
}

GltfSampler RandomSampler(SplitMix64& rng, bool rotation) {
  GltfSampler s;
  s.interpolation = static_cast<GltfInterpolation>(rng.Next() % 3);
  s.width = rotation ? 4 : 1 + static_cast<int>(rng.Next() % 4);
  const int keys = 2 + static_cast<int>(rng.Next() % 8);
  double t = rng.Unit() * 2 - 1;
  for (int k = 0; k < keys; ++k) {
    s.times.push_back(t);
    if (rng.Unit() > 0.15) t += rng.Unit() * 0.5;  // else a zero-length interval
  }
  const int per_key = s.interpolation == GltfInterpolation::kCubicSpline ? 3 : 1;
  for (int k = 0; k < keys * per_key; ++k) {
    if (rotation) {
      Quat q = RandomQuat(rng);
      if (k > 0 && rng.Unit() < 0.2 && per_key == 1) {  // nearly the previous key
        double len = 0;
        for (int i = 0; i < 4; ++i) {
          q[i] = s.values[s.values.size() - 4 + i] + 1e-5 * q[i];
          len += q[i] * q[i];
        }
        for (double& x : q) x /= std::sqrt(len);  // glTF rotations are unit quaternions
      }
      s.values.insert(s.values.end(), q.begin(), q.end());
    } else {
      for (int i = 0; i < s.width; ++i) s.values.push_back(rng.Unit() * 20 - 10);
    }
  }
  return s;
}

TEST(GltfAnimationPropertyTest, SamplersAgreeWithTheReference) {
  SplitMix64 rng(31);
  int checked = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const bool rotation = rng.Unit() < 0.5;
    const GltfSampler s = RandomSampler(rng, rotation);
    for (int e = 0; e < 20; ++e) {
      double tc = s.times.front() - 0.2 + rng.Unit() * (s.times.back() - s.times.front() + 0.4);
      if (e < 3) tc = s.times[rng.Next() % s.times.size()];  // exactly on a key
      const std::vector<double> got = Eval(s, rotation, tc);
      const std::vector<double> want = ReferenceEval(s, rotation, tc);
      ASSERT_EQ(got.size(), want.size());
      for (size_t i = 0; i < got.size(); ++i) {
        ASSERT_NEAR(got[i], want[i], 1e-9) << "trial " << trial << " time " << tc << " i " << i;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 60000);
}

using Mat4 = std::array<double, 16>;  // column-major

Mat4 Mul(const Mat4& a, const Mat4& b) {
  Mat4 out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) out[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return out;
}

// q v q* for a unit q.
std::array<double, 3> Rotate(const Quat& q, const std::array<double, 3>& v) {
  const Quat p = {v[0], v[1], v[2], 0};
  auto hamilton = [](const Quat& a, const Quat& b) {
    return Quat{a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
                a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
                a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
                a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
  };
  const Quat r = hamilton(hamilton(q, p), {-q[0], -q[1], -q[2], q[3]});
  return {r[0], r[1], r[2]};
}

Mat4 ReferenceLocal(const GltfNodeTransform& n) {
  if (n.has_matrix) return n.matrix;
  Mat4 m{};
  for (int c = 0; c < 3; ++c) {
    std::array<double, 3> axis = {0, 0, 0};
    axis[c] = n.scale[c];
    const std::array<double, 3> column = Rotate(n.rotation, axis);
    for (int r = 0; r < 3; ++r) m[c * 4 + r] = column[r];
  }
  for (int r = 0; r < 3; ++r) m[12 + r] = n.translation[r];
  m[15] = 1;
  return m;
}

TEST(GltfAnimationPropertyTest, JointPositionsAgreeWithMatrices) {
  SplitMix64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int nodes = 1 + static_cast<int>(rng.Next() % 12);
    GltfHierarchy h;
    h.parent.resize(static_cast<size_t>(nodes));
    h.rest.resize(static_cast<size_t>(nodes));
    // Parents are random earlier nodes after a random relabelling, so indices are not in
    // parent-first order; the order lists them depth-first.
    std::vector<int> label(static_cast<size_t>(nodes));
    for (int i = 0; i < nodes; ++i) label[static_cast<size_t>(i)] = i;
    for (int i = nodes - 1; i > 0; --i) std::swap(label[static_cast<size_t>(i)], label[rng.Next() % (i + 1)]);
    for (int i = 0; i < nodes; ++i) {
      const int node = label[static_cast<size_t>(i)];
      h.parent[static_cast<size_t>(node)] =
          i == 0 || rng.Unit() < 0.1 ? -1 : label[rng.Next() % static_cast<uint64_t>(i)];
      h.order.push_back(node);
      GltfNodeTransform& rest = h.rest[static_cast<size_t>(node)];
      for (double& x : rest.translation) x = rng.Unit() * 2 - 1;
      rest.rotation = RandomQuat(rng);
      for (double& x : rest.scale) x = 0.5 + rng.Unit();
    }
    GltfClip clip;
    for (int c = 0; c < 6; ++c) {
      GltfChannel channel;
      channel.node = static_cast<int>(rng.Next() % static_cast<uint64_t>(nodes));
      channel.path = static_cast<GltfPath>(rng.Next() % 3);
      channel.sampler = c;
      GltfSampler s = RandomSampler(rng, channel.path == GltfPath::kRotation);
      if (channel.path != GltfPath::kRotation) {  // VEC3 values
        s.width = 3;
        s.values.clear();
        const int per_key = s.interpolation == GltfInterpolation::kCubicSpline ? 3 : 1;
        for (size_t k = 0; k < s.times.size() * per_key * 3; ++k) s.values.push_back(0.5 + rng.Unit());
      }
      clip.samplers.push_back(s);
      clip.channels.push_back(channel);
    }
    std::vector<int> joints;
    for (int n = 0; n < nodes; ++n) {
      if (rng.Unit() < 0.7) joints.push_back(n);
    }
    const double start = GltfClipStart(clip);
    const double fps = 10;
    const int64_t frames = GltfFrameCount(clip, fps);
    const std::vector<double> got = GltfJointPositions(h, clip, joints, start, fps, frames);
    ASSERT_EQ(got.size(), static_cast<size_t>(frames) * joints.size() * 3);
    for (int64_t f = 0; f < frames; ++f) {
      const double time = start + static_cast<double>(f) / fps;
      std::vector<GltfNodeTransform> pose = h.rest;
      for (const GltfChannel& channel : clip.channels) {
        const bool rot = channel.path == GltfPath::kRotation;
        const std::vector<double> v =
            ReferenceEval(clip.samplers[static_cast<size_t>(channel.sampler)], rot, time,
                          GltfSnapSeconds(time, fps));
        GltfNodeTransform& n = pose[static_cast<size_t>(channel.node)];
        if (channel.path == GltfPath::kTranslation) std::copy(v.begin(), v.end(), n.translation.begin());
        if (rot) std::copy(v.begin(), v.end(), n.rotation.begin());
        if (channel.path == GltfPath::kScale) std::copy(v.begin(), v.end(), n.scale.begin());
      }
      for (size_t j = 0; j < joints.size(); ++j) {
        Mat4 world = ReferenceLocal(pose[static_cast<size_t>(joints[j])]);
        for (int p = h.parent[static_cast<size_t>(joints[j])]; p >= 0; p = h.parent[static_cast<size_t>(p)]) {
          world = Mul(ReferenceLocal(pose[static_cast<size_t>(p)]), world);
        }
        for (int r = 0; r < 3; ++r) {
          ASSERT_NEAR(got[(static_cast<size_t>(f) * joints.size() + j) * 3 + static_cast<size_t>(r)],
                      world[12 + r], 1e-8)
              << "trial " << trial << " frame " << f << " joint " << joints[j];
        }
      }
    }
  }
}

}  // namespace
}  // namespace koma

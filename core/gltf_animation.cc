#include "core/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/trig_degrees.h"

namespace koma {
namespace {

constexpr double kDegreesPerRadian = 57.295779513082320876798154814105;
// Below this |dot| slerp's weights are well conditioned; above it (quaternions within about
// 1.8 degrees) a normalised lerp is used, as the glTF specification's reference does.
constexpr double kSlerpLimit = 0.9995;
// The median key spacing at or below which keys count as a baked rate (20 fps).
constexpr double kDenseSpacingSeconds = 1.0 / 20.0;
constexpr double kSparseFps = 30.0;

using Quat = std::array<double, 4>;

Quat Normalised(const Quat& q) {
  const double length_squared = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (!(length_squared > 0)) return q;
  const double inverse = 1.0 / std::sqrt(length_squared);
  return {q[0] * inverse, q[1] * inverse, q[2] * inverse, q[3] * inverse};
}

// 3 x 4 affine transform, column-major like glTF: m[column * 3 + row], column 3 translation.
using Affine = std::array<double, 12>;

Affine FromTrs(const std::array<double, 3>& t, const Quat& q, const std::array<double, 3>& s) {
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  // The rotation matrix of a unit quaternion, each column scaled by its scale factor.
  const double r00 = 1 - 2 * (y * y + z * z), r01 = 2 * (x * y - z * w), r02 = 2 * (x * z + y * w);
  const double r10 = 2 * (x * y + z * w), r11 = 1 - 2 * (x * x + z * z), r12 = 2 * (y * z - x * w);
  const double r20 = 2 * (x * z - y * w), r21 = 2 * (y * z + x * w), r22 = 1 - 2 * (x * x + y * y);
  return {r00 * s[0], r10 * s[0], r20 * s[0], r01 * s[1], r11 * s[1], r21 * s[1],
          r02 * s[2], r12 * s[2], r22 * s[2], t[0],       t[1],       t[2]};
}

Affine FromMatrix(const std::array<double, 16>& m) {
  return {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10], m[12], m[13], m[14]};
}

Affine Multiply(const Affine& a, const Affine& b) {
  Affine out;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) {
      double v = a[r] * b[c * 3] + a[3 + r] * b[c * 3 + 1] + a[6 + r] * b[c * 3 + 2];
      if (c == 3) v += a[9 + r];
      out[c * 3 + r] = v;
    }
  }
  return out;
}

// The interval [k, k + 1) holding `time`, or the key `time` is on / clamped to.
struct Place {
  size_t key = 0;
  bool exact = true;  // the value of `key` itself
  double t = 0;       // with !exact: the fraction of the interval, in (0, 1)
  double length = 0;  // with !exact: the interval, seconds
};

Place Locate(const std::vector<double>& times, double time, double snap) {
  // The last key at or before time + snap: on it when it is within snap of `time` (the later
  // of equal keys: a zero-length interval is a jump), or when it is the last key.
  const size_t upper = static_cast<size_t>(
      std::upper_bound(times.begin(), times.end(), time + snap) - times.begin());
  if (upper == 0) return {0};  // before the first key
  const size_t k = upper - 1;
  if (times[k] >= time - snap || k + 1 == times.size()) return {k};
  // times[k] < time - snap and times[k + 1] > time + snap: inside the interval.
  const double length = times[k + 1] - times[k];
  return {k, false, (time - times[k]) / length, length};
}

}  // namespace

double AcosDegrees(double d) {
  if (d >= 1) return 0;
  if (d <= 0) return 90;
  // Abramowitz and Stegun 4.4.45 (error below 7e-5 rad) as the start, then Newton steps on
  // cos(theta) = d; each squares the error (theta >= 1.8 degrees where slerp calls this).
  const double start = std::sqrt(1 - d) *
                       (1.5707288 + d * (-0.2121144 + d * (0.0742610 + d * -0.0187293)));
  double theta = start * kDegreesPerRadian;
  for (int i = 0; i < 5; ++i) {
    const SinCos sc = SinCosDegrees(theta);
    if (!(sc.sin > 0)) break;
    theta += (sc.cos - d) / sc.sin * kDegreesPerRadian;
  }
  return theta;
}

Quat GltfSlerp(const Quat& a, const Quat& b, double t) {
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  double sign = 1;
  if (d < 0) {  // the shorter arc: q and -q are the same rotation
    d = -d;
    sign = -1;
  }
  double wa = 1 - t;
  double wb = sign * t;
  if (d <= kSlerpLimit) {
    const double theta = AcosDegrees(d);
    const double inverse_sin = 1.0 / SinCosDegrees(theta).sin;
    wa = SinCosDegrees(theta * (1 - t)).sin * inverse_sin;
    wb = sign * SinCosDegrees(theta * t).sin * inverse_sin;
    return {wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2],
            wa * a[3] + wb * b[3]};
  }
  return Normalised(
      {wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2], wa * a[3] + wb * b[3]});
}

void EvaluateGltfSampler(const GltfSampler& sampler, bool rotation, double time, double snap,
                         double* out) {
  const int w = sampler.width;
  const bool cubic = sampler.interpolation == GltfInterpolation::kCubicSpline;
  const size_t stride = cubic ? 3 * static_cast<size_t>(w) : static_cast<size_t>(w);
  const size_t value_offset = cubic ? static_cast<size_t>(w) : 0;  // past the in-tangent
  const Place place = Locate(sampler.times, time, snap);
  const double* v0 = sampler.values.data() + place.key * stride + value_offset;
  if (place.exact || sampler.interpolation == GltfInterpolation::kStep) {
    std::copy(v0, v0 + w, out);
    return;
  }
  const double* v1 = v0 + stride;
  const double t = place.t;
  if (sampler.interpolation == GltfInterpolation::kLinear) {
    if (rotation) {
      const Quat q = GltfSlerp({v0[0], v0[1], v0[2], v0[3]}, {v1[0], v1[1], v1[2], v1[3]}, t);
      std::copy(q.begin(), q.end(), out);
      return;
    }
    for (int i = 0; i < w; ++i) out[i] = (1 - t) * v0[i] + t * v1[i];
    return;
  }
  // CUBICSPLINE (Appendix C): p(t) = (2t^3 - 3t^2 + 1) v_k + td (t^3 - 2t^2 + t) b_k
  //                                 + (-2t^3 + 3t^2) v_k+1 + td (t^3 - t^2) a_k+1,
  // b_k the out-tangent of key k, a_k+1 the in-tangent of key k + 1, td the interval.
  const double* out_tangent = v0 + w;
  const double* in_tangent = v1 - w;
  const double t2 = t * t;
  const double t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1;
  const double h10 = place.length * (t3 - 2 * t2 + t);
  const double h01 = -2 * t3 + 3 * t2;
  const double h11 = place.length * (t3 - t2);
  for (int i = 0; i < w; ++i) {
    out[i] = h00 * v0[i] + h10 * out_tangent[i] + h01 * v1[i] + h11 * in_tangent[i];
  }
  if (rotation) {
    const Quat q = Normalised({out[0], out[1], out[2], out[3]});
    std::copy(q.begin(), q.end(), out);
  }
}

double GltfClipStart(const GltfClip& clip) {
  double start = 0;
  bool first = true;
  for (const GltfSampler& s : clip.samplers) {
    if (s.times.empty()) continue;
    if (first || s.times.front() < start) start = s.times.front();
    first = false;
  }
  return start;
}

double GltfClipEnd(const GltfClip& clip) {
  double end = 0;
  bool first = true;
  for (const GltfSampler& s : clip.samplers) {
    if (s.times.empty()) continue;
    if (first || s.times.back() > end) end = s.times.back();
    first = false;
  }
  return end;
}

double GltfAutoSourceFps(const GltfClip& clip) {
  std::vector<double> spacings;
  for (const GltfSampler& s : clip.samplers) {
    for (size_t k = 1; k < s.times.size(); ++k) {
      const double gap = s.times[k] - s.times[k - 1];
      if (gap > 0) spacings.push_back(gap);
    }
  }
  if (spacings.empty()) return kSparseFps;
  const size_t middle = spacings.size() / 2;
  std::nth_element(spacings.begin(), spacings.begin() + static_cast<std::ptrdiff_t>(middle),
                   spacings.end());
  const double median = spacings[middle];
  if (median > kDenseSpacingSeconds) return kSparseFps;
  const double fps = 1.0 / median;
  const double whole = std::floor(fps + 0.5);
  return std::fabs(fps - whole) <= 1e-3 * fps ? whole : fps;
}

int64_t GltfFrameCount(const GltfClip& clip, double fps) {
  const double span = (GltfClipEnd(clip) - GltfClipStart(clip)) * fps;  // in frames
  if (!(span > 1e-4)) return 1;
  // Beyond any frame limit (a fuzzed key time of 1e22 s): saturate instead of an undefined
  // double-to-integer conversion; the caller's limit check refuses it.
  constexpr double kSaturated = 4.0e18;
  if (!(span < kSaturated)) return static_cast<int64_t>(kSaturated);
  const double whole = std::floor(span + 1e-4);
  int64_t frames = static_cast<int64_t>(whole) + 1;
  if (span - whole > 1e-4) ++frames;  // the end falls between frames: one more, clamped
  return frames;
}

double GltfSnapSeconds(double time, double fps) {
  const double float_ulps = 8 * 1.1920928955078125e-07 * std::max(1.0, std::fabs(time));
  return std::min(float_ulps, 1e-3 / fps);
}

std::vector<double> GltfJointPositions(const GltfHierarchy& hierarchy, const GltfClip& clip,
                                       const std::vector<int>& joints, double start, double fps,
                                       int64_t frames) {
  const size_t node_count = hierarchy.rest.size();
  std::vector<double> positions(static_cast<size_t>(frames) * joints.size() * 3);
  std::vector<GltfNodeTransform> pose = hierarchy.rest;
  std::vector<Affine> world(node_count);
  double value[4];
  for (int64_t f = 0; f < frames; ++f) {
    const double time = start + static_cast<double>(f) / fps;
    const double snap = GltfSnapSeconds(time, fps);
    for (const GltfChannel& channel : clip.channels) {
      GltfNodeTransform& node = pose[static_cast<size_t>(channel.node)];
      const GltfSampler& sampler = clip.samplers[static_cast<size_t>(channel.sampler)];
      switch (channel.path) {
        case GltfPath::kTranslation:
          EvaluateGltfSampler(sampler, false, time, snap, value);
          std::copy(value, value + 3, node.translation.begin());
          break;
        case GltfPath::kRotation:
          EvaluateGltfSampler(sampler, true, time, snap, value);
          std::copy(value, value + 4, node.rotation.begin());
          break;
        case GltfPath::kScale:
          EvaluateGltfSampler(sampler, false, time, snap, value);
          std::copy(value, value + 3, node.scale.begin());
          break;
        case GltfPath::kWeights:
          break;  // morph weights deform meshes, not joints
      }
    }
    for (int n : hierarchy.order) {
      const GltfNodeTransform& node = pose[static_cast<size_t>(n)];
      const Affine local = node.has_matrix ? FromMatrix(node.matrix)
                                           : FromTrs(node.translation, node.rotation, node.scale);
      const int parent = hierarchy.parent[static_cast<size_t>(n)];
      world[static_cast<size_t>(n)] =
          parent < 0 ? local : Multiply(world[static_cast<size_t>(parent)], local);
    }
    double* dst = positions.data() + static_cast<size_t>(f) * joints.size() * 3;
    for (int j : joints) {
      const Affine& m = world[static_cast<size_t>(j)];
      *dst++ = m[9];
      *dst++ = m[10];
      *dst++ = m[11];
    }
  }
  return positions;
}

}  // namespace koma

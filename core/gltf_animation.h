// glTF 2.0 animation on plain types: sampler evaluation exactly as the glTF 2.0 specification's
// Appendix C ("Animation Sampler Interpolation Modes") gives it, the source rate of an
// animation (glTF key times are seconds, with no frame rate), and the world positions of a node
// hierarchy's joints at every sampled frame (docs/semantics.md, "glTF animations").
//
// Units: times in seconds; translations in the file's length unit (metres by glTF's
// convention); rotations as unit quaternions (x, y, z, w); scales and morph weights unitless.
// Only +, -, *, /, sqrt and core/trig_degrees.h on the answer's path (no libm), so the same
// file gives the same bits everywhere (docs/semantics.md, "Determinism").
#ifndef KOMA_CORE_GLTF_ANIMATION_H_
#define KOMA_CORE_GLTF_ANIMATION_H_

#include <array>
#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"

namespace koma {

enum class GltfInterpolation : uint8_t { kLinear, kStep, kCubicSpline };
enum class GltfPath : uint8_t { kTranslation, kRotation, kScale, kWeights };

// One animation sampler with its accessors decoded.
struct GltfSampler {
  GltfInterpolation interpolation = GltfInterpolation::kLinear;
  // Key times, seconds, finite and non-decreasing (equal neighbours make a zero-length
  // interval, which is never evaluated inside: the later key wins from its time on).
  std::vector<double> times;
  // Values per key: `width` numbers (LINEAR, STEP), or in-tangent, value, out-tangent of
  // `width` numbers each (CUBICSPLINE), key after key.
  std::vector<double> values;
  // Numbers per value: 3 (translation, scale), 4 (rotation) or the morph-target count.
  int width = 3;
};

// The sampler's value at `time` seconds into out[0 .. width). Before the first key: the first
// value; after the last: the last. LINEAR interpolates linearly, rotations by slerp (the
// shorter arc; normalised lerp when the quaternions are within 1.8 degrees, |dot| > 0.9995,
// where slerp's 1 / sin loses precision); STEP holds the previous key; CUBICSPLINE is the
// Hermite spline with the interval's length scaling the tangents, a rotation normalised.
// A time within `snap` seconds of a key is that key (sampling at k / fps lands on keys that
// files store as 32-bit floats, e.g. 1/24 s as 0.041666668 s).
// Requires times non-empty, non-decreasing, values.size() == times.size() x width
// (x 3 for CUBICSPLINE), width 4 when `rotation`.
void EvaluateGltfSampler(const GltfSampler& sampler, bool rotation, double time, double snap,
                         double* out);

// Slerp of unit quaternions a and b (x, y, z, w) at t in [0, 1], as above.
std::array<double, 4> GltfSlerp(const std::array<double, 4>& a, const std::array<double, 4>& b,
                                double t);

// arccos(d) in degrees for d in [0, 1], from SinCosDegrees by Newton's method: no libm.
double AcosDegrees(double d);

// A node's rest transform: TRS, or a matrix (column-major, as glTF stores it).
struct GltfNodeTransform {
  std::array<double, 3> translation = {0, 0, 0};
  std::array<double, 4> rotation = {0, 0, 0, 1};
  std::array<double, 3> scale = {1, 1, 1};
  bool has_matrix = false;  // glTF forbids animating such a node
  std::array<double, 16> matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

// One channel: which node property a sampler drives.
struct GltfChannel {
  int node = 0;
  GltfPath path = GltfPath::kTranslation;
  int sampler = 0;
};

struct GltfClip {
  std::vector<GltfSampler> samplers;
  std::vector<GltfChannel> channels;
};

// The first and last key time over the clip's samplers, seconds.
double GltfClipStart(const GltfClip& clip);
double GltfClipEnd(const GltfClip& clip);

// The rate the clip is sampled at when the request gives none, frames per second: where keys
// are dense (the median spacing between a sampler's successive keys is at most 1/20 s, as in
// the 24, 30 or 60 fps a DCC bakes) their rate, rounded to a whole number when within 0.1 %;
// otherwise (sparse hand-set keys such as a pose every 0.5 s) 30.
double GltfAutoSourceFps(const GltfClip& clip);

// Frames sampled at `fps` from the clip's start to its end: frame k at start + k / fps, the
// last at or just after the end (within 1e-4 of a frame counts as on it). At least 1.
int64_t GltfFrameCount(const GltfClip& clip, double fps);

// The hierarchy the joints live in. parent[i] is node i's parent or -1; order lists nodes with
// parents before children (every node whose world transform is needed).
struct GltfHierarchy {
  std::vector<int> parent;
  std::vector<GltfNodeTransform> rest;
  std::vector<int> order;
};

// World positions of `joints` (node indices) at frames 0 .. frames - 1 (frame k at
// start + k / fps seconds), frame-major: frames x joints x 3. Each node's local transform is
// its rest TRS with the clip's channels in place (translation, rotation, scale; weights do
// not move joints), T * R * S, or its matrix; world = parent world * local.
// Requires channels to name nodes of `hierarchy`, and every joint and its ancestors in order.
std::vector<double> GltfJointPositions(const GltfHierarchy& hierarchy, const GltfClip& clip,
                                       const std::vector<int>& joints, double start, double fps,
                                       int64_t frames);

// The snap tolerance EvaluateGltfSampler gets at `time` when sampling a file: about 8 ulp of
// a 32-bit float there, and never more than a thousandth of a frame at `fps`.
double GltfSnapSeconds(double time, double fps);

}  // namespace koma

#endif  // KOMA_CORE_GLTF_ANIMATION_H_

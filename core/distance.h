// The frame distance of RetimeSkeletal: dist(a, b) = sum_i w_i * |Q_a[i] - Q_b[i]|^2 over
// joints i, where Q are the joint positions after the optional transforms (root-relative,
// camera projection). Computed in double, joints in index order, components x, y(, z) in
// order, so every implementation gets bit-identical values (the tie rules depend on it).
#ifndef KOMA_CORE_DISTANCE_H_
#define KOMA_CORE_DISTANCE_H_

#include <array>
#include <optional>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/types/span.h"
#include "core/large_array.h"

namespace koma {

struct DistanceOptions {
  // One weight per joint, finite and >= 0; empty means all 1.
  std::vector<double> weights;
  // Subtract joint 0's position (the root) in the same frame before comparing, so
  // locomotion does not dominate the speed measure. Applied in world space, before the
  // camera projection below.
  bool root_relative = false;
  // 4x4 view-projection matrix, column-major (OpenGL/glTF): element (row r, column c) is
  // camera[4 * c + r]. When set, each position p (root-relative first, if asked: the pose
  // is moved so its root sits at the world origin, then viewed) becomes
  // clip = M * (p.x, p.y, p.z, 1) and then normalised device coordinates
  // (clip.x / clip.w, clip.y / clip.w); the distance uses those 2 components: screen-space
  // speed.
  std::optional<std::array<double, 16>> camera;
};

class FrameDistance {
 public:
  // `world_positions` is frame-major: frame_count x joint_count x 3 (x, y, z).
  // INVALID_ARGUMENT (message names the field, e.g. "weights[3]: -1 is negative") when
  // frame_count or joint_count < 1, sizes disagree, a position or camera entry is not
  // finite, a weight is negative or not finite, or a projected point has w == 0 (or a
  // non-finite result). Joints of weight 0 take no part: their points are stored as 0 and
  // never projected, so they cannot fail the camera check nor turn a sum into NaN.
  static absl::StatusOr<FrameDistance> Create(absl::Span<const double> world_positions,
                                              int frame_count, int joint_count,
                                              const DistanceOptions& options);

  // The same, but when no transform applies (no root_relative, no camera, every weight > 0)
  // it reads `world_positions` in place instead of copying them: they must outlive the
  // result. The server uses it over the request's packed field (a 100k-frame, 31-joint clip
  // is 74 MB that need not be copied). With a transform it copies, as Create does.
  static absl::StatusOr<FrameDistance> CreateView(absl::Span<const double> world_positions,
                                                  int frame_count, int joint_count,
                                                  const DistanceOptions& options);

  // Move-only: `points_` may point into `owned_`, which a move keeps and a copy would not.
  FrameDistance(FrameDistance&&) = default;
  FrameDistance& operator=(FrameDistance&&) = default;
  FrameDistance(const FrameDistance&) = delete;
  FrameDistance& operator=(const FrameDistance&) = delete;

  int frame_count() const { return frame_count_; }
  int joint_count() const { return joint_count_; }

  // dist(a, b) for source frames a and b; O(joint_count). Exactly
  //   sum = 0; for i in joints: sum += w_i * (dx * dx + dy * dy [+ dz * dz])
  // with d = Q_a[i] - Q_b[i]. Always >= 0 (may be +inf on overflow, never NaN).
  double operator()(int a, int b) const;

  // The per-frame SSD of the input: ssd[0] = 0, ssd[k] = dist(k - 1, k).
  std::vector<double> InputSsd() const;
  // The same bits, four frames at a time: ~1.5x faster while the clip fits the caches
  // (Pitch size 4.8 -> 3.1 us), ~3x slower on a clip of 100k frames or more (strided reads).
  std::vector<double> InputSsdOfSmallClip() const;

  // One streaming pass for RetimeFast: ssd[k] = dist(k - 1, k) as InputSsd,
  // skip[k] = dist(k - 1, k + 1) for 1 <= k <= N - 2 and skip2[k] = dist(k - 1, k + 2) for
  // 1 <= k <= N - 3 (0 elsewhere), each bit-identical to operator() (same summation order).
  // Any pointer may be null; non-null vectors are resized to frame_count.
  // `Vector` is std::vector<double> or LargeArray<double> (core/large_array.h).
  template <typename Vector>
  void AdjacentDistances(Vector* ssd, Vector* skip, Vector* skip2 = nullptr) const;

 private:
  FrameDistance() = default;
  int frame_count_ = 0;
  int joint_count_ = 0;
  int dims_ = 3;  // 3, or 2 after camera projection
  // The transformed points, unless read in place; a LargeArray (every distance
  // pass reads them, the holds at random).
  LargeArray<double> owned_;
  absl::Span<const double> points_;  // frame_count x joint_count x dims_: owned_ or a view
  std::vector<double> weights_;      // joint_count
};

}  // namespace koma

#endif  // KOMA_CORE_DISTANCE_H_

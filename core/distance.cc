#include "core/distance.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/huge_page_vector.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"

namespace koma {
namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};

// Two doubles operated on lane by lane (a GCC/Clang vector extension: SSE2 on x86-64, NEON on
// ARM, scalar code elsewhere). Each lane's +, -, * is the IEEE double operation, so a lane
// computes exactly what the same scalar expression does.
typedef double Lanes __attribute__((vector_size(16)));

absl::Status ValidateSizes(absl::Span<const double> world_positions, int frame_count,
                           int joint_count) {
  if (frame_count < 1) {
    return absl::InvalidArgumentError(absl::StrCat("frame_count: ", frame_count, " must be >= 1"));
  }
  if (joint_count < 1) {
    return absl::InvalidArgumentError(absl::StrCat("joint_count: ", joint_count, " must be >= 1"));
  }
  const int64_t expected = int64_t{frame_count} * joint_count * 3;
  if (static_cast<int64_t>(world_positions.size()) != expected) {
    return absl::InvalidArgumentError(
        absl::StrCat("world_positions: expected ", expected, " values (", frame_count, " frames x ",
                     joint_count, " joints x 3), got ", world_positions.size()));
  }
  if (AllFinite(world_positions)) return absl::OkStatus();  // one vectorised pass
  for (size_t k = 0; k < world_positions.size(); ++k) {
    if (!std::isfinite(world_positions[k])) {
      const size_t point = k / 3;
      return absl::InvalidArgumentError(absl::StrCat(
          "world_positions[", k, "]: ", world_positions[k], " is not finite (frame ",
          point / joint_count, " joint ", point % joint_count, " ", kAxisNames[k % 3], ")"));
    }
  }
  return absl::OkStatus();
}

// Empty weights mean all 1; otherwise one finite, non-negative weight per joint.
absl::StatusOr<std::vector<double>> CheckedWeights(const std::vector<double>& weights,
                                                   int joint_count) {
  if (weights.empty()) return std::vector<double>(joint_count, 1.0);
  if (static_cast<int64_t>(weights.size()) != joint_count) {
    return absl::InvalidArgumentError(
        absl::StrCat("weights: ", weights.size(), " weights for ", joint_count,
                     " joints (give one per joint, or none for all 1)"));
  }
  for (size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i])) {
      return absl::InvalidArgumentError(
          absl::StrCat("weights[", i, "]: ", weights[i], " is not finite"));
    }
    if (weights[i] < 0.0) {
      return absl::InvalidArgumentError(
          absl::StrCat("weights[", i, "]: ", weights[i], " is negative"));
    }
  }
  return weights;
}

absl::Status CheckCameraEntries(const std::array<double, 16>& m) {
  for (size_t k = 0; k < m.size(); ++k) {
    if (!std::isfinite(m[k])) {
      return absl::InvalidArgumentError(absl::StrCat("camera[", k, "]: ", m[k], " is not finite"));
    }
  }
  return absl::OkStatus();
}

// Projects the 3D point p of (frame, joint) with the column-major matrix m and writes its
// normalised device coordinates (x/w, y/w) to out[0..1].
absl::Status Project(const std::array<double, 16>& m, const double* p, int frame, int joint,
                     double* out) {
  const double x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
  const double y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
  const double w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  if (w == 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("camera: frame ", frame, " joint ", joint, " projects with w = 0"));
  }
  out[0] = x / w;
  out[1] = y / w;
  if (!std::isfinite(out[0]) || !std::isfinite(out[1])) {
    return absl::InvalidArgumentError(absl::StrCat("camera: frame ", frame, " joint ", joint,
                                                   " projects to (", out[0], ", ", out[1],
                                                   "), not finite (w = ", w, ")"));
  }
  return absl::OkStatus();
}

// Every dist(a, b) is at most sum(w) * dims * (2 * max|coordinate|)^2. Requiring that bound
// to stay well below DBL_MAX (a factor 8 covers rounding in the summation order) keeps every
// distance finite, so the candidate orderings never meet inf or NaN.
absl::Status CheckDistanceBound(absl::Span<const double> points, const std::vector<double>& weights,
                                int dims) {
  // The largest |coordinate| (inf or NaN when one is not finite), in one vectorised pass.
  const uint64_t largest_bits = LargestMagnitudeBits(points);
  double largest;
  std::memcpy(&largest, &largest_bits, sizeof(largest));
  double total_weight = 0.0;
  for (double w : weights) total_weight += w;
  const double bound = total_weight * dims * (2.0 * largest) * (2.0 * largest);
  if (std::isfinite(largest) && bound < std::numeric_limits<double>::max() / 8) {
    return absl::OkStatus();
  }
  return absl::OutOfRangeError(
      absl::StrCat("positions: largest |coordinate| ", largest, " with total weight ", total_weight,
                   " would overflow the frame distance (squared, in double); scale the clip down"));
}

}  // namespace

absl::StatusOr<FrameDistance> FrameDistance::Create(absl::Span<const double> world_positions,
                                                    int frame_count, int joint_count,
                                                    const DistanceOptions& options) {
  KOMA_RETURN_IF_ERROR(ValidateSizes(world_positions, frame_count, joint_count));
  FrameDistance distance;
  KOMA_ASSIGN_OR_RETURN(distance.weights_, CheckedWeights(options.weights, joint_count));
  if (options.camera.has_value()) KOMA_RETURN_IF_ERROR(CheckCameraEntries(*options.camera));
  distance.frame_count_ = frame_count;
  distance.joint_count_ = joint_count;
  distance.dims_ = options.camera.has_value() ? 2 : 3;
  const int dims = distance.dims_;
  distance.owned_.assign(static_cast<size_t>(frame_count) * joint_count * dims, 0.0);
  for (int f = 0; f < frame_count; ++f) {
    const double* frame = world_positions.data() + static_cast<size_t>(f) * joint_count * 3;
    for (int j = 0; j < joint_count; ++j) {
      // Zero-weight joints stay at 0: they add exactly 0 and are never projected.
      if (distance.weights_[j] == 0.0) continue;
      double p[3] = {frame[3 * j], frame[3 * j + 1], frame[3 * j + 2]};
      if (options.root_relative) {
        for (int c = 0; c < 3; ++c) p[c] -= frame[c];
      }
      double* out = distance.owned_.data() + (static_cast<size_t>(f) * joint_count + j) * dims;
      if (options.camera.has_value()) {
        KOMA_RETURN_IF_ERROR(Project(*options.camera, p, f, j, out));
      } else {
        for (int c = 0; c < 3; ++c) out[c] = p[c];
      }
    }
  }
  distance.points_ = absl::MakeConstSpan(distance.owned_);
  KOMA_RETURN_IF_ERROR(CheckDistanceBound(distance.points_, distance.weights_, dims));
  return distance;
}

absl::StatusOr<FrameDistance> FrameDistance::CreateView(absl::Span<const double> world_positions,
                                                        int frame_count, int joint_count,
                                                        const DistanceOptions& options) {
  KOMA_RETURN_IF_ERROR(ValidateSizes(world_positions, frame_count, joint_count));
  FrameDistance distance;
  KOMA_ASSIGN_OR_RETURN(distance.weights_, CheckedWeights(options.weights, joint_count));
  const bool identity = !options.root_relative && !options.camera.has_value() &&
                        std::all_of(distance.weights_.begin(), distance.weights_.end(),
                                    [](double w) { return w > 0.0; });
  if (!identity) return Create(world_positions, frame_count, joint_count, options);
  distance.frame_count_ = frame_count;
  distance.joint_count_ = joint_count;
  distance.dims_ = 3;
  distance.points_ = world_positions;
  KOMA_RETURN_IF_ERROR(CheckDistanceBound(distance.points_, distance.weights_, 3));
  return distance;
}

double FrameDistance::operator()(int a, int b) const {
  const size_t stride = static_cast<size_t>(joint_count_) * dims_;
  const double* pa = points_.data() + static_cast<size_t>(a) * stride;
  const double* pb = points_.data() + static_cast<size_t>(b) * stride;
  double sum = 0.0;
  if (dims_ == 3) {
    for (int i = 0; i < joint_count_; ++i, pa += 3, pb += 3) {
      const double dx = pa[0] - pb[0];
      const double dy = pa[1] - pb[1];
      const double dz = pa[2] - pb[2];
      sum += weights_[i] * (dx * dx + dy * dy + dz * dz);
    }
  } else {
    for (int i = 0; i < joint_count_; ++i, pa += 2, pb += 2) {
      const double dx = pa[0] - pb[0];
      const double dy = pa[1] - pb[1];
      sum += weights_[i] * (dx * dx + dy * dy);
    }
  }
  return sum;
}

std::vector<double> FrameDistance::InputSsd() const {
  std::vector<double> ssd(frame_count_, 0.0);
  for (int k = 1; k < frame_count_; ++k) ssd[k] = (*this)(k - 1, k);
  return ssd;
}

template <typename Vector>
void FrameDistance::AdjacentDistances(Vector* ssd, Vector* skip, Vector* skip2) const {
  const int n = frame_count_;
  if (ssd != nullptr) ssd->assign(n, 0.0);
  if (skip != nullptr) skip->assign(n, 0.0);
  if (skip2 != nullptr) skip2->assign(n, 0.0);
  if (ssd == nullptr || skip == nullptr || skip2 == nullptr || dims_ != 3) {
    // Not the hot case: the plain loops.
    for (int k = 1; k < n; ++k) {
      if (ssd != nullptr) (*ssd)[k] = (*this)(k - 1, k);
      if (skip != nullptr && k + 1 < n) (*skip)[k] = (*this)(k - 1, k + 1);
      if (skip2 != nullptr && k + 2 < n) (*skip2)[k] = (*this)(k - 1, k + 2);
    }
    return;
  }
  // Frames k - 1 .. k + 2 are read together, so the extra distances cost arithmetic only, not
  // memory traffic. Arithmetic is what limits this loop, so dist(k - 1, k) and dist(k - 1, k + 1)
  // share SIMD registers, one per lane; dist(k - 1, k + 2) is scalar. Each lane performs exactly
  // the scalar operations of operator(), joints in index order, so the results are
  // bit-identical. (Left to itself, GCC vectorises across joint pairs instead, which needs
  // shuffles for every joint's sum: 10-15 % slower at 1M frames x 31 joints.)
  const size_t stride = static_cast<size_t>(joint_count_) * 3;
  const double* w = weights_.data();
  double* out_ssd = ssd->data();
  double* out_skip = skip->data();
  double* out_skip2 = skip2->data();
  int k = 1;
  for (; k + 2 < n; ++k) {
    const double* pa = points_.data() + static_cast<size_t>(k - 1) * stride;
    const double* pb = pa + stride;
    const double* pc = pb + stride;
    const double* pd = pc + stride;
    Lanes sum_abc = {0.0, 0.0};  // dist(k - 1, k), dist(k - 1, k + 1)
    double sum_ad = 0.0;         // dist(k - 1, k + 2)
    for (int i = 0; i < joint_count_; ++i, pa += 3, pb += 3, pc += 3, pd += 3) {
      Lanes bc[3];  // per axis: pa - pb, pa - pc
      double d[3];  // per axis: pa - pd
      for (int c = 0; c < 3; ++c) {
        bc[c] = Lanes{pa[c], pa[c]} - Lanes{pb[c], pc[c]};
        d[c] = pa[c] - pd[c];
      }
      sum_abc += Lanes{w[i], w[i]} * (bc[0] * bc[0] + bc[1] * bc[1] + bc[2] * bc[2]);
      sum_ad += w[i] * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    out_ssd[k] = sum_abc[0];
    out_skip[k] = sum_abc[1];
    out_skip2[k] = sum_ad;
  }
  for (; k < n; ++k) {
    out_ssd[k] = (*this)(k - 1, k);
    if (k + 1 < n) out_skip[k] = (*this)(k - 1, k + 1);
  }
}

template void FrameDistance::AdjacentDistances(std::vector<double>*, std::vector<double>*,
                                               std::vector<double>*) const;
template void FrameDistance::AdjacentDistances(HugePageVector<double>*, HugePageVector<double>*,
                                               HugePageVector<double>*) const;

}  // namespace koma

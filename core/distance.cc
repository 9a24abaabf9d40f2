#include "core/distance.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/large_array.h"
#include "core/magnitude_scan.h"
#include "core/status_macros.h"
#include "core/target_clones.h"

namespace koma {
namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};

// Also gives the bit pattern of the largest |coordinate| (core/magnitude_scan.h) in
// `largest_bits`: the one scan of the positions serves both this check and the distance bound
// when the distances read the positions as they are (CreateView).
absl::Status ValidateSizes(absl::Span<const double> world_positions, int frame_count,
                           int joint_count, uint64_t& largest_bits) {
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
  largest_bits = LargestMagnitudeBits(world_positions);  // one vectorised pass
  if (largest_bits < kNonFiniteBits) return absl::OkStatus();
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
// `largest_bits`: LargestMagnitudeBits of the points the distances read.
absl::Status CheckDistanceBound(uint64_t largest_bits, const std::vector<double>& weights,
                                int dims) {
  double largest;  // the largest |coordinate| (inf or NaN when one is not finite)
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

// Four doubles operated on lane by lane (a GCC/Clang vector extension): one AVX2 register in
// the AVX2 build, two SSE2 registers in the plain x86-64 one, scalar code elsewhere. Each
// lane's +, -, * is the IEEE double operation (no FMA: -ffp-contract=off), so a lane computes
// exactly what the same scalar expression does. Declared alignment 8, as in
// core/forward_kinematics.cc: the two builds must agree, and the table reads below are not
// 32-byte aligned anyway.
typedef double Lanes4 __attribute__((vector_size(32), aligned(8)));

// Values of k per block of AdjacentDistancesInBlocks (a multiple of 4). The block's table is
// 3 * joints rows x (kBlockFrames + 3) doubles: 26 KB for 31 joints, so it stays in L1.
constexpr int kBlockFrames = 32;

// ssd[k], skip[k] and skip2[k] (see AdjacentDistances) for k = 1 .. (return value) - 1, in
// blocks of kBlockFrames values of k; the caller computes the rest. dims 3.
//
// A block first copies the frames it reads (k - 1 .. k + 2 for each of its k) into a table
// with one row per coordinate (joint i, axis c) and one column per frame, reading the frames
// front to back. Then four consecutive k are computed side by side, one per lane: in a
// coordinate's row, the lanes' frames k - 1, k, k + 1 and k + 2 are four loads at columns
// 0..3 from the group's first, and each lane performs exactly operator()'s scalar operations
// for its k, in the same order (joints in index order, (dx * dx + dy * dy) + dz * dz, times
// w, added to the sum), so the results are bit-identical. Per distance that is about a third
// of the instructions of taking one k at a time with its four frames side by side.
//
// While a block computes, its successor's frames are prefetched into the L2/L3 caches (not
// L1, which the table occupies): without that the copy waited on memory and the pass ran at
// ~110 ms on the 1M-frame clip instead of ~65 ms (~90 ms before the table).
// Built for plain x86-64 and for AVX2, picked at load time by the CPU.
KOMA_TARGET_CLONES("avx2", "default")
int AdjacentDistancesInBlocks(const double* points, const double* weights, int frame_count,
                              int joint_count, double* ssd, double* skip, double* skip2) {
  constexpr int kColumns = kBlockFrames + 3;  // frames first - 1 .. first + kBlockFrames + 1
  const size_t coordinates = static_cast<size_t>(joint_count) * 3;
  std::vector<double> table(coordinates * kColumns);
  int first = 1;  // the block's first k
  // A block reads frames up to first + kBlockFrames + 1, which must exist.
  for (; first + kBlockFrames + 1 < frame_count; first += kBlockFrames) {
    const double* frame = points + static_cast<size_t>(first - 1) * coordinates;
    for (int column = 0; column < kColumns; ++column, frame += coordinates) {
      for (size_t r = 0; r < coordinates; ++r) table[r * kColumns + column] = frame[r];
    }
    // The next block's frames (3 * joints * (kBlockFrames + 3) doubles, ~13 lines per joint),
    // two lines per joint and group of four: all of them over the block's 8 groups.
    const char* next_block = reinterpret_cast<const char*>(frame - 3 * coordinates);
    const char* const next_end = next_block + kColumns * coordinates * sizeof(double);
    for (int lane0 = 0; lane0 < kBlockFrames; lane0 += 4) {
      Lanes4 sum_ssd = {0.0, 0.0, 0.0, 0.0};  // dist(k - 1, k) for k = first + lane0 + lane
      Lanes4 sum_skip = sum_ssd;              // dist(k - 1, k + 1)
      Lanes4 sum_skip2 = sum_ssd;             // dist(k - 1, k + 2)
      const double* row = table.data() + lane0;
      for (int i = 0; i < joint_count; ++i) {
        Lanes4 d1[3], d2[3], d3[3];  // per axis: frame k - 1 minus frame k, k + 1, k + 2
        for (int c = 0; c < 3; ++c, row += kColumns) {
          Lanes4 a, b, e, g;
          __builtin_memcpy(&a, row, sizeof a);
          __builtin_memcpy(&b, row + 1, sizeof b);
          __builtin_memcpy(&e, row + 2, sizeof e);
          __builtin_memcpy(&g, row + 3, sizeof g);
          d1[c] = a - b;
          d2[c] = a - e;
          d3[c] = a - g;
        }
        for (int line = 0; line < 2 && next_block < next_end; ++line, next_block += 64) {
          __builtin_prefetch(next_block, 0, 1);
        }
        const Lanes4 w = {weights[i], weights[i], weights[i], weights[i]};
        sum_ssd += w * (d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]);
        sum_skip += w * (d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]);
        sum_skip2 += w * (d3[0] * d3[0] + d3[1] * d3[1] + d3[2] * d3[2]);
      }
      const int k = first + lane0;
      __builtin_memcpy(ssd + k, &sum_ssd, sizeof sum_ssd);
      __builtin_memcpy(skip + k, &sum_skip, sizeof sum_skip);
      __builtin_memcpy(skip2 + k, &sum_skip2, sizeof sum_skip2);
    }
  }
  return first;
}

// ssd[k] = dist(k - 1, k) for k = 1 .. (return value) - 1, four values of k side by side, one
// per lane, each lane performing operator()'s scalar operations in its order (bit-identical).
// operator() is one chain of dependent additions, ~36 ns for 31 joints here; four independent
// chains share that time. Each lane reads its frames straight from `points`, four strided
// streams, which is only fast while the clip is in the caches (see InputSsdOfSmallClip).
KOMA_TARGET_CLONES("avx2", "default")
int AdjacentSsdInLanes(const double* points, const double* weights, int frame_count,
                       int joint_count, double* ssd) {
  const size_t coordinates = static_cast<size_t>(joint_count) * 3;
  int k = 1;
  for (; k + 3 < frame_count; k += 4) {
    const double* before = points + static_cast<size_t>(k - 1) * coordinates;  // lane l: k-1+l
    Lanes4 sum = {0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < joint_count; ++i) {
      Lanes4 d[3];
      for (int c = 0; c < 3; ++c) {
        const double* p = before + 3 * i + c;
        const Lanes4 a = {p[0], p[coordinates], p[2 * coordinates], p[3 * coordinates]};
        const Lanes4 b = {p[coordinates], p[2 * coordinates], p[3 * coordinates],
                          p[4 * coordinates]};
        d[c] = a - b;
      }
      const Lanes4 w = {weights[i], weights[i], weights[i], weights[i]};
      sum += w * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    __builtin_memcpy(ssd + k, &sum, sizeof sum);
  }
  return k;
}

}  // namespace

absl::StatusOr<FrameDistance> FrameDistance::Create(absl::Span<const double> world_positions,
                                                    int frame_count, int joint_count,
                                                    const DistanceOptions& options) {
  uint64_t input_largest_bits = 0;  // of the input; the transformed points are scanned below
  KOMA_RETURN_IF_ERROR(
      ValidateSizes(world_positions, frame_count, joint_count, input_largest_bits));
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
  KOMA_RETURN_IF_ERROR(
      CheckDistanceBound(LargestMagnitudeBits(distance.points_), distance.weights_, dims));
  return distance;
}

absl::StatusOr<FrameDistance> FrameDistance::CreateView(absl::Span<const double> world_positions,
                                                        int frame_count, int joint_count,
                                                        const DistanceOptions& options) {
  uint64_t largest_bits = 0;
  KOMA_RETURN_IF_ERROR(ValidateSizes(world_positions, frame_count, joint_count, largest_bits));
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
  KOMA_RETURN_IF_ERROR(CheckDistanceBound(largest_bits, distance.weights_, 3));
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

std::vector<double> FrameDistance::InputSsdOfSmallClip() const {
  std::vector<double> ssd(frame_count_, 0.0);
  int k = 1;
  if (dims_ == 3) {
    k = AdjacentSsdInLanes(points_.data(), weights_.data(), frame_count_, joint_count_,
                           ssd.data());
  }
  for (; k < frame_count_; ++k) ssd[k] = (*this)(k - 1, k);
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
  const int done = AdjacentDistancesInBlocks(points_.data(), weights_.data(), n, joint_count_,
                                             ssd->data(), skip->data(), skip2->data());
  for (int k = std::max(done, 1); k < n; ++k) {
    (*ssd)[k] = (*this)(k - 1, k);
    if (k + 1 < n) (*skip)[k] = (*this)(k - 1, k + 1);
    if (k + 2 < n) (*skip2)[k] = (*this)(k - 1, k + 2);
  }
}

template void FrameDistance::AdjacentDistances(std::vector<double>*, std::vector<double>*,
                                               std::vector<double>*) const;
template void FrameDistance::AdjacentDistances(LargeArray<double>*, LargeArray<double>*,
                                               LargeArray<double>*) const;

}  // namespace koma

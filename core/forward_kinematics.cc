#include "core/forward_kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/trig_degrees.h"

namespace koma {
namespace {

// Four frames are computed side by side, one per SIMD lane: the transforms of a joint go through
// the same operations in every frame (only the values differ), so each lane performs exactly
// the scalar operations of one frame, in the same order, and gets the same bits. Lanes is a
// GCC/Clang vector extension: two SSE2 registers on plain x86-64, one AVX2 register in the AVX2
// build (see FillWorldPositions), scalar code elsewhere; no FMA (-ffp-contract=off).
// Its declared alignment is 8: GCC aligns a 32-byte vector to 32 in the AVX2 build but to 16 in
// the plain one, where std::vector allocates the transforms below; with alignment 8 every
// access is an unaligned one (no cost on current x86 cores) and both builds agree.
typedef double Lanes __attribute__((vector_size(32), aligned(8)));
constexpr int kLanes = 4;

// Vectors are passed by reference and the helpers are inlined: a 32-byte vector passed by value
// has a different ABI in the AVX2 and the plain build.
#define KOMA_FK_INLINE __attribute__((always_inline)) inline

// A rigid transform of four frames: x' = rotation * x + translation. rotation is row-major 3x3.
struct LaneTransform {
  Lanes rotation[9];
  Lanes translation[3];
};

KOMA_FK_INLINE void Broadcast(double value, Lanes& out) { out = Lanes{value, value, value, value}; }

// Lane l = column[l * stride]: one channel's entry in four consecutive frames.
KOMA_FK_INLINE void Gather(const double* column, size_t stride, Lanes& out) {
  out = Lanes{column[0], column[stride], column[2 * stride], column[3 * stride]};
}

// rotation := rotation * R_axis(degrees), the right-handed rotation about the channel's axis
// (intrinsic: later channels multiply on the right). R_axis has only a 2x2 block, so each
// row mixes two columns (i, k): 12 multiplications instead of a full 3x3 product's 27.
// `s` and `c` are the sine and cosine of the channel's angle. The columns are template
// arguments so that `rotation` (a local array) stays in registers: with indices known only at
// run time it lived in memory, and each rotation waited on the stores of the one before.
template <int i, int k>
KOMA_FK_INLINE void RotateColumns(const Lanes& s, const Lanes& c, Lanes (&rotation)[9]) {
  for (int r = 0; r < 3; ++r) {
    const Lanes a = rotation[3 * r + i];
    const Lanes b = rotation[3 * r + k];
    rotation[3 * r + i] = c * a + s * b;
    rotation[3 * r + k] = c * b - s * a;
  }
}

// Columns (i, k) of the block: X mixes y,z; Y mixes z,x; Z mixes x,y. In each case
// new_i = c * old_i + s * old_k and new_k = c * old_k - s * old_i.
KOMA_FK_INLINE void RotateAbout(ChannelKind kind, const Lanes& s, const Lanes& c,
                                Lanes (&rotation)[9]) {
  switch (kind) {
    case ChannelKind::kXRotation:
      RotateColumns<1, 2>(s, c, rotation);
      break;
    case ChannelKind::kYRotation:
      RotateColumns<2, 0>(s, c, rotation);
      break;
    default:  // kZRotation
      RotateColumns<0, 1>(s, c, rotation);
      break;
  }
}

KOMA_FK_INLINE bool IsRotation(ChannelKind kind) {
  return kind == ChannelKind::kXRotation || kind == ChannelKind::kYRotation ||
         kind == ChannelKind::kZRotation;
}

// The world transform of one joint in four frames: parent * T(offset) * T(position channels) *
// R(c1) * R(c2) * ... (identity for the root's parent). `values` points at the joint's first
// channel in the first frame (frames are `stride` apart); `sin` and `cos` at the sines and
// cosines of its rotation channels (angles in degrees), four frames' worth per channel, in
// channel order (only read when `with_rotation`). The translation is the parent's
// transform applied to the local one; the rotation starts as the parent's and each rotation
// channel multiplies it on the right in place (12 multiplications each), so no 3x3 product
// is needed. It is only computed when `with_rotation` (a joint's own rotation moves its
// children, never itself).
KOMA_FK_INLINE void JointTransform(const Joint& joint, const LaneTransform* parent,
                                   const double* values, const double* sin, const double* cos,
                                   size_t stride, bool with_rotation, LaneTransform& world) {
  Lanes local[3];  // the local translation
  Broadcast(joint.offset.x, local[0]);
  Broadcast(joint.offset.y, local[1]);
  Broadcast(joint.offset.z, local[2]);
  for (size_t c = 0; c < joint.channels.size(); ++c) {
    const ChannelKind kind = joint.channels[c];
    if (kind == ChannelKind::kXPosition || kind == ChannelKind::kYPosition ||
        kind == ChannelKind::kZPosition) {
      Lanes value;
      Gather(values + c, stride, value);
      local[static_cast<int>(kind) - static_cast<int>(ChannelKind::kXPosition)] += value;
    }
  }
  Lanes rotation[9] = {};  // the world rotation, in registers while the channels turn it
  if (parent == nullptr) {
    constexpr double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int r = 0; r < 3; ++r) world.translation[r] = local[r];
    if (!with_rotation) return;
    for (int e = 0; e < 9; ++e) Broadcast(kIdentity[e], rotation[e]);
  } else {
    for (int r = 0; r < 3; ++r) {
      world.translation[r] = parent->translation[r] + parent->rotation[3 * r] * local[0] +
                             parent->rotation[3 * r + 1] * local[1] +
                             parent->rotation[3 * r + 2] * local[2];
    }
    if (!with_rotation) return;
    for (int e = 0; e < 9; ++e) rotation[e] = parent->rotation[e];
  }
  for (const ChannelKind kind : joint.channels) {
    if (IsRotation(kind)) {
      Lanes s, co;
      __builtin_memcpy(&s, sin, sizeof s);
      __builtin_memcpy(&co, cos, sizeof co);
      sin += kLanes;
      cos += kLanes;
      RotateAbout(kind, s, co, rotation);
    }
  }
  for (int e = 0; e < 9; ++e) world.rotation[e] = rotation[e];
}

// out[kLanes * k + l] = rows[l * stride + channel + k] for k < length and each lane l: a run
// of consecutive channels of four frames, channel by channel with the frames side by side.
// Four channels at a time are four loads, a 4 x 4 transpose in registers and four stores,
// instead of sixteen single loads and stores (which were ~13 % of forward kinematics).
KOMA_FK_INLINE void TransposeRun(const double* rows, size_t stride, size_t channel, size_t length,
                                 double* out) {
  typedef long long Mask __attribute__((vector_size(32)));
  size_t k = 0;
  for (; k + kLanes <= length; k += kLanes) {
    // Separate variables, not arrays: GCC kept arrays of vectors on the stack.
    Lanes r0, r1, r2, r3;
    const double* first = rows + channel + k;
    __builtin_memcpy(&r0, first, sizeof r0);
    __builtin_memcpy(&r1, first + stride, sizeof r1);
    __builtin_memcpy(&r2, first + 2 * stride, sizeof r2);
    __builtin_memcpy(&r3, first + 3 * stride, sizeof r3);
    const Lanes t0 = __builtin_shuffle(r0, r1, Mask{0, 4, 2, 6});
    const Lanes t1 = __builtin_shuffle(r0, r1, Mask{1, 5, 3, 7});
    const Lanes t2 = __builtin_shuffle(r2, r3, Mask{0, 4, 2, 6});
    const Lanes t3 = __builtin_shuffle(r2, r3, Mask{1, 5, 3, 7});
    const Lanes c0 = __builtin_shuffle(t0, t2, Mask{0, 1, 4, 5});
    const Lanes c1 = __builtin_shuffle(t1, t3, Mask{0, 1, 4, 5});
    const Lanes c2 = __builtin_shuffle(t0, t2, Mask{2, 3, 6, 7});
    const Lanes c3 = __builtin_shuffle(t1, t3, Mask{2, 3, 6, 7});
    double* to = out + kLanes * k;
    __builtin_memcpy(to, &c0, sizeof c0);
    __builtin_memcpy(to + kLanes, &c1, sizeof c1);
    __builtin_memcpy(to + 2 * kLanes, &c2, sizeof c2);
    __builtin_memcpy(to + 3 * kLanes, &c3, sizeof c3);
  }
  for (; k < length; ++k) {
    for (int l = 0; l < kLanes; ++l) out[kLanes * k + l] = rows[l * stride + channel + k];
  }
}

// The positions of every joint in every frame (see ComputeWorldPositions; the sizes are
// checked there), four frames at a time. Built for plain x86-64 and for AVX2, picked at load
// time; the same IEEE operations either way (tests/core/forward_kinematics_test pins the bits
// against a one-frame-at-a-time reference).
__attribute__((target_clones("avx2", "default"))) void FillWorldPositions(
    const std::vector<Joint>& joints, const double* values, int frame_count, int channel_count,
    double* positions) {
  const size_t joint_count = joints.size();
  std::vector<bool> has_children(joint_count, false);
  for (const Joint& joint : joints) {
    if (joint.parent >= 0) has_children[joint.parent] = true;
  }
  // The rotation channels whose angles are used: those of joints with children (a leaf's own
  // rotation moves nothing), as channel indices within a frame, in joint and channel order.
  std::vector<size_t> first_channel(joint_count, 0);
  std::vector<size_t> first_angle(joint_count, 0);  // the joint's first entry in angle_channels
  std::vector<size_t> angle_channels;
  for (size_t j = 0, channel = 0; j < joint_count; ++j) {
    first_channel[j] = channel;
    first_angle[j] = angle_channels.size();
    for (const ChannelKind kind : joints[j].channels) {
      if (has_children[j] && IsRotation(kind)) angle_channels.push_back(channel);
      ++channel;
    }
  }
  // The same channels as runs of consecutive ones (a joint's rotation channels usually are):
  // {first channel, first index in angle_channels, length}.
  struct ChannelRun {
    size_t channel, angle, length;
  };
  std::vector<ChannelRun> runs;
  for (size_t a = 0; a < angle_channels.size(); ++a) {
    if (!runs.empty() && runs.back().channel + runs.back().length == angle_channels[a]) {
      ++runs.back().length;
    } else {
      runs.push_back({angle_channels[a], a, 1});
    }
  }
  const size_t stride = static_cast<size_t>(channel_count);
  std::vector<LaneTransform> world(joint_count);  // this group's world transforms
  // The group's used angles, channel by channel with the four frames side by side, and their
  // sines and cosines, all at once (a vectorised loop). Not std::sin and std::cos: their last
  // bits differ between libms, and these bits reach the distances, the tie rules and the
  // response.
  std::vector<double> angles(kLanes * angle_channels.size());
  std::vector<double> sin(angles.size());
  std::vector<double> cos(angles.size());
  std::vector<double> last_group;  // the last frames, padded with zeros to four
  for (int f = 0; f < frame_count; f += kLanes) {
    const int frames = std::min(kLanes, frame_count - f);
    const double* group = values + static_cast<size_t>(f) * stride;
    if (frames < kLanes) {
      last_group.assign(kLanes * stride, 0.0);
      std::copy(group, group + frames * stride, last_group.begin());
      group = last_group.data();
    }
    for (const ChannelRun& run : runs) {
      TransposeRun(group, stride, run.channel, run.length, angles.data() + kLanes * run.angle);
    }
    SinCosDegrees(angles.data(), static_cast<int>(angles.size()), sin.data(), cos.data());
    for (size_t j = 0; j < joint_count; ++j) {
      const Joint& joint = joints[j];
      // Parents precede children (ValidateSkeleton rule 2), so world[parent] is ready.
      const LaneTransform* parent = joint.parent < 0 ? nullptr : &world[joint.parent];
      const size_t angle = kLanes * first_angle[j];
      JointTransform(joint, parent, group + first_channel[j], sin.data() + angle,
                     cos.data() + angle, stride, has_children[j], world[j]);
      for (int l = 0; l < frames; ++l) {
        double* out = positions + (static_cast<size_t>(f + l) * joint_count + j) * 3;
        for (int axis = 0; axis < 3; ++axis) out[axis] = world[j].translation[axis][l];
      }
    }
  }
}

#undef KOMA_FK_INLINE

}  // namespace

absl::StatusOr<HugePageVector<double>> ComputeWorldPositions(const Skeleton& skeleton,
                                                             absl::Span<const double> values,
                                                             int frame_count, int threads,
                                                             size_t capacity_doubles) {
  KOMA_RETURN_IF_ERROR(ValidateSkeleton(skeleton));
  const std::vector<Joint>& joints = skeleton.joints;
  const int channel_count = ChannelCount(skeleton);
  if (frame_count < 0) {
    return absl::InvalidArgumentError(absl::StrCat("frame_count: ", frame_count, " is negative"));
  }
  const int64_t expected = int64_t{frame_count} * channel_count;
  if (static_cast<int64_t>(values.size()) != expected) {
    return absl::InvalidArgumentError(absl::StrCat("values: expected ", expected, " values (",
                                                   frame_count, " frames x ", channel_count,
                                                   " channels), got ", values.size()));
  }
  const size_t doubles = static_cast<size_t>(frame_count) * joints.size() * 3;
  HugePageVector<double> positions;
  positions.reserve(std::max(doubles, capacity_doubles));
  positions.resize(doubles);  // not zeroed (HugePageAllocator::construct)
  // Stretches of whole four-frame groups (the lanes), one per thread.
  const int used = std::max(1, std::min(threads, frame_count / kFramesPerFkThread));
  const int stretch = (frame_count / used + kLanes - 1) / kLanes * kLanes;
  auto fill = [&](int first) {
    const int count = std::min(stretch, frame_count - first);
    FillWorldPositions(joints, values.data() + static_cast<size_t>(first) * channel_count, count,
                       channel_count,
                       positions.data() + static_cast<size_t>(first) * joints.size() * 3);
  };
  std::vector<std::thread> helpers;
  for (int first = stretch; first < frame_count; first += stretch)
    helpers.emplace_back(fill, first);
  fill(0);
  for (std::thread& helper : helpers) helper.join();
  return positions;
}

absl::StatusOr<HugePageVector<double>> ComputeWorldPositions(const SkeletalClip& clip) {
  return ComputeWorldPositions(clip.skeleton, clip.values, clip.frame_count);
}

}  // namespace koma

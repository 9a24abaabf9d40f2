#include "core/forward_kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "core/target_clones.h"
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

// What the frame loop needs of a joint, worked out once per call so that the loop does not
// walk each joint's channel list (and test each channel's kind) in every group of frames.
// ValidateSkeleton allows at most 6 channels per joint, none repeated: at most three
// position and three rotation channels.
struct JointPlan {
  int parent = -1;
  double offset[3] = {};       // x, y, z
  size_t first_channel = 0;    // the joint's first channel within a frame
  size_t first_angle = 0;      // its first rotation channel among the angles used
  bool with_rotation = false;  // it has children, so its rotation is used
  int position_count = 0;
  size_t position_channel[3] = {};  // within the joint, in channel order
  int position_axis[3] = {};        // 0 x, 1 y, 2 z
  int rotation_count = 0;
  ChannelKind rotation_axis[3] = {};  // in channel order
};

// The world transform of one joint in four frames: parent * T(offset) * T(position channels) *
// R(c1) * R(c2) * ... (identity for the root's parent). `values` points at the joint's first
// channel in the first frame (frames are `stride` apart); `sin` and `cos` at the sines and
// cosines of its rotation channels (angles in degrees), four frames' worth per channel, in
// channel order (only read when the joint's rotation is used). The translation is the
// parent's transform applied to the local one; the rotation starts as the parent's and each
// rotation channel multiplies it on the right in place (12 multiplications each), so no 3x3
// product is needed. It is only computed for a joint with children (a joint's own rotation
// moves its children, never itself). `rotations` and `translations` hold every joint's world
// transform in this group: 9 and 3 Lanes per joint, row-major rotation.
KOMA_FK_INLINE void JointTransform(const JointPlan& plan, size_t index, const double* values,
                                   const double* sin, const double* cos, size_t stride,
                                   Lanes* rotations, Lanes* translations) {
  Lanes local[3];  // the local translation
  for (int axis = 0; axis < 3; ++axis) Broadcast(plan.offset[axis], local[axis]);
  for (int p = 0; p < plan.position_count; ++p) {
    Lanes value;
    Gather(values + plan.position_channel[p], stride, value);
    local[plan.position_axis[p]] += value;
  }
  Lanes* translation = translations + 3 * index;
  Lanes rotation[9] = {};  // the world rotation, in registers while the channels turn it
  if (plan.parent < 0) {
    constexpr double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int r = 0; r < 3; ++r) translation[r] = local[r];
    if (!plan.with_rotation) return;
    for (int e = 0; e < 9; ++e) Broadcast(kIdentity[e], rotation[e]);
  } else {
    const Lanes* parent_rotation = rotations + 9 * plan.parent;
    const Lanes* parent_translation = translations + 3 * plan.parent;
    for (int r = 0; r < 3; ++r) {
      translation[r] = parent_translation[r] + parent_rotation[3 * r] * local[0] +
                       parent_rotation[3 * r + 1] * local[1] +
                       parent_rotation[3 * r + 2] * local[2];
    }
    if (!plan.with_rotation) return;
    for (int e = 0; e < 9; ++e) rotation[e] = parent_rotation[e];
  }
  for (int a = 0; a < plan.rotation_count; ++a) {
    Lanes s, co;
    __builtin_memcpy(&s, sin + kLanes * a, sizeof s);
    __builtin_memcpy(&co, cos + kLanes * a, sizeof co);
    RotateAbout(plan.rotation_axis[a], s, co, rotation);
  }
  for (int e = 0; e < 9; ++e) rotations[9 * index + e] = rotation[e];
}

// to[l * to_stride + k] = from[k * from_stride + l] for k, l < 4: a 4 x 4 block of doubles
// transposed with four loads, eight shuffles and four stores (instead of sixteen single loads
// and stores, which were ~13 % of forward kinematics where the angles are read and ~10 %
// where the positions are written).
KOMA_FK_INLINE void Transpose4x4(const double* from, size_t from_stride, double* to,
                                 size_t to_stride) {
  // Lane i of the result is lane i_k of the eight lanes of (a, b): GCC's __builtin_shuffle,
  // or clang's __builtin_shufflevector (the sanitizer and fuzz builds use clang).
#if defined(__clang__)
#define KOMA_SHUFFLE4(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
  typedef long long Mask __attribute__((vector_size(32)));
#define KOMA_SHUFFLE4(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, Mask{i0, i1, i2, i3})
#endif
  // Separate variables, not arrays: GCC kept arrays of vectors on the stack.
  Lanes r0, r1, r2, r3;
  __builtin_memcpy(&r0, from, sizeof r0);
  __builtin_memcpy(&r1, from + from_stride, sizeof r1);
  __builtin_memcpy(&r2, from + 2 * from_stride, sizeof r2);
  __builtin_memcpy(&r3, from + 3 * from_stride, sizeof r3);
  const Lanes t0 = KOMA_SHUFFLE4(r0, r1, 0, 4, 2, 6);
  const Lanes t1 = KOMA_SHUFFLE4(r0, r1, 1, 5, 3, 7);
  const Lanes t2 = KOMA_SHUFFLE4(r2, r3, 0, 4, 2, 6);
  const Lanes t3 = KOMA_SHUFFLE4(r2, r3, 1, 5, 3, 7);
  const Lanes c0 = KOMA_SHUFFLE4(t0, t2, 0, 1, 4, 5);
  const Lanes c1 = KOMA_SHUFFLE4(t1, t3, 0, 1, 4, 5);
  const Lanes c2 = KOMA_SHUFFLE4(t0, t2, 2, 3, 6, 7);
  const Lanes c3 = KOMA_SHUFFLE4(t1, t3, 2, 3, 6, 7);
  __builtin_memcpy(to, &c0, sizeof c0);
  __builtin_memcpy(to + to_stride, &c1, sizeof c1);
  __builtin_memcpy(to + 2 * to_stride, &c2, sizeof c2);
  __builtin_memcpy(to + 3 * to_stride, &c3, sizeof c3);
#undef KOMA_SHUFFLE4
}

// out[kLanes * k + l] = rows[l * stride + channel + k] for k < length and each lane l: a run
// of consecutive channels of four frames, channel by channel with the frames side by side.
KOMA_FK_INLINE void TransposeRun(const double* rows, size_t stride, size_t channel, size_t length,
                                 double* out) {
  size_t k = 0;
  for (; k + kLanes <= length; k += kLanes) {
    Transpose4x4(rows + channel + k, stride, out + kLanes * k, kLanes);
  }
  for (; k < length; ++k) {
    for (int l = 0; l < kLanes; ++l) out[kLanes * k + l] = rows[l * stride + channel + k];
  }
}

// The inverse for the positions: rows[l * stride + k] = lanes[kLanes * k + l] for k < length
// and l < frames (four frames' rows of `length` doubles, `stride` apart, from values held
// lane by lane).
KOMA_FK_INLINE void UntransposeRows(const double* lanes, size_t length, int frames, size_t stride,
                                    double* rows) {
  size_t k = 0;
  if (frames == kLanes) {
    for (; k + kLanes <= length; k += kLanes) {
      Transpose4x4(lanes + kLanes * k, kLanes, rows + k, stride);
    }
  }
  for (; k < length; ++k) {
    for (int l = 0; l < frames; ++l) rows[l * stride + k] = lanes[kLanes * k + l];
  }
}

// The positions of every joint in every frame (see ComputeWorldPositions; the sizes are
// checked there), four frames at a time. Built for plain x86-64 and for AVX2, picked at load
// time; the same IEEE operations either way (tests/core/forward_kinematics_test pins the bits
// against a one-frame-at-a-time reference).
KOMA_TARGET_CLONES("avx2", "default")
void FillWorldPositions(const std::vector<Joint>& joints, const double* values, int frame_count,
                        int channel_count, double* positions) {
  const size_t joint_count = joints.size();
  std::vector<JointPlan> plans(joint_count);
  for (size_t j = 0; j < joint_count; ++j) {
    plans[j].parent = joints[j].parent;
    plans[j].offset[0] = joints[j].offset.x;
    plans[j].offset[1] = joints[j].offset.y;
    plans[j].offset[2] = joints[j].offset.z;
    if (joints[j].parent >= 0) plans[joints[j].parent].with_rotation = true;
  }
  // The rotation channels whose angles are used: those of joints with children (a leaf's own
  // rotation moves nothing), as channel indices within a frame, in joint and channel order.
  std::vector<size_t> angle_channels;
  angle_channels.reserve(static_cast<size_t>(channel_count));  // one allocation, not ~8
  for (size_t j = 0, channel = 0; j < joint_count; ++j) {
    JointPlan& plan = plans[j];
    plan.first_channel = channel;
    plan.first_angle = angle_channels.size();
    for (size_t c = 0; c < joints[j].channels.size(); ++c, ++channel) {
      const ChannelKind kind = joints[j].channels[c];
      if (!IsRotation(kind)) {
        plan.position_channel[plan.position_count] = c;
        plan.position_axis[plan.position_count++] =
            static_cast<int>(kind) - static_cast<int>(ChannelKind::kXPosition);
      } else if (plan.with_rotation) {
        plan.rotation_axis[plan.rotation_count++] = kind;
        angle_channels.push_back(channel);
      }
    }
  }
  // The same channels as runs of consecutive ones (a joint's rotation channels usually are):
  // {first channel, first index in angle_channels, length}.
  struct ChannelRun {
    size_t channel, angle, length;
  };
  std::vector<ChannelRun> runs;
  runs.reserve(joint_count);  // usually one run per joint
  for (size_t a = 0; a < angle_channels.size(); ++a) {
    if (!runs.empty() && runs.back().channel + runs.back().length == angle_channels[a]) {
      ++runs.back().length;
    } else {
      runs.push_back({angle_channels[a], a, 1});
    }
  }
  const size_t stride = static_cast<size_t>(channel_count);
  // This group's world transforms; the translations of all joints side by side are the
  // group's positions, lane by lane.
  // Held as doubles (std::vector would drop Lanes' alignment attribute); GCC lets a vector
  // type alias its element type.
  std::vector<double> rotation_storage(kLanes * 9 * joint_count);
  std::vector<double> translation_storage(kLanes * 3 * joint_count);
  Lanes* const rotations = reinterpret_cast<Lanes*>(rotation_storage.data());
  Lanes* const translations = reinterpret_cast<Lanes*>(translation_storage.data());
  // The group's used angles, channel by channel with the four frames side by side, and their
  // sines and cosines, all at once (a vectorised loop). Not std::sin and std::cos: their last
  // bits differ between libms, and these bits reach the distances, the tie rules and the
  // response.
  std::vector<double> angles(kLanes * angle_channels.size());
  std::vector<double> sin(angles.size());
  std::vector<double> cos(angles.size());
  std::vector<double> last_group;                   // the last frames, padded with zeros to four
  const size_t row = 3 * joint_count;               // doubles of positions per frame
  StopPoll stop(/*steps_between_checks=*/1 << 16);  // joint transforms: a check every ~1 ms
  for (int f = 0; f < frame_count; f += kLanes) {
    // Stopped: the rest stays unfilled; ComputeWorldPositions returns the stop instead.
    if (stop.Stop(static_cast<int64_t>(kLanes * joint_count))) break;
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
      // Parents precede children (ValidateSkeleton rule 2), so their transforms are ready.
      const JointPlan& plan = plans[j];
      const size_t angle = kLanes * plan.first_angle;
      JointTransform(plan, j, group + plan.first_channel, sin.data() + angle, cos.data() + angle,
                     stride, rotations, translations);
    }
    UntransposeRows(translation_storage.data(), row, frames, row,
                    positions + static_cast<size_t>(f) * row);
  }
}

#undef KOMA_FK_INLINE

}  // namespace

absl::StatusOr<LargeArray<double>> ComputeWorldPositions(const Skeleton& skeleton,
                                                         absl::Span<const double> values,
                                                         int frame_count, const TaskRunner& runner,
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
  LargeArray<double> positions;
  positions.reserve(std::max(doubles, capacity_doubles));
  positions.resize(doubles);  // not zeroed (LargeArrayAllocator::construct)
  // Stretches of whole four-frame groups (the lanes), one per task.
  const int used = std::max(1, std::min(runner.Parallelism(), frame_count / kFramesPerFkThread));
  const int stretch = (frame_count / used + kLanes - 1) / kLanes * kLanes;
  const int stretches = used == 1 ? 1 : (frame_count + stretch - 1) / stretch;
  runner.Run(stretches, [&](int index) {
    const int first = index * stretch;
    const int count = std::min(stretch, frame_count - first);
    FillWorldPositions(joints, values.data() + static_cast<size_t>(first) * channel_count, count,
                       channel_count,
                       positions.data() + static_cast<size_t>(first) * joints.size() * 3);
  });
  KOMA_RETURN_IF_ERROR(StopReason());  // a stopped fill left positions unfinished
  return positions;
}

absl::StatusOr<LargeArray<double>> ComputeWorldPositions(const SkeletalClip& clip) {
  return ComputeWorldPositions(clip.skeleton, clip.values, clip.frame_count);
}

}  // namespace koma

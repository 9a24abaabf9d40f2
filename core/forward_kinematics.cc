#include "core/forward_kinematics.h"

#include <cmath>
#include <cstdint>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/trig_degrees.h"

namespace koma {
namespace {

// A rigid transform: x' = rotation * x + translation. rotation is row-major 3x3.
struct Transform {
  double rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double translation[3] = {0, 0, 0};
};

// out = a * b for row-major 3x3 matrices (out must not alias a or b).
void Multiply3(const double* a, const double* b, double* out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
    }
  }
}

// rotation := rotation * R_axis(degrees), the right-handed rotation about the channel's axis
// (intrinsic: later channels multiply on the right). R_axis has only a 2x2 block, so each
// row mixes two entries: 12 multiplications instead of a full 3x3 product's 27.
// `s` and `c` are the sine and cosine of the channel's angle.
void RotateAbout(ChannelKind kind, double s, double c, double* rotation) {
  // Columns (i, k) of the block: X mixes y,z; Y mixes z,x; Z mixes x,y. In each case
  // new_i = c * old_i + s * old_k and new_k = c * old_k - s * old_i.
  int i = 0;
  int k = 1;
  if (kind == ChannelKind::kXRotation) {
    i = 1;
    k = 2;
  } else if (kind == ChannelKind::kYRotation) {
    i = 2;
    k = 0;
  }
  for (int r = 0; r < 3; ++r) {
    const double a = rotation[3 * r + i];
    const double b = rotation[3 * r + k];
    rotation[3 * r + i] = c * a + s * b;
    rotation[3 * r + k] = c * b - s * a;
  }
}

// T(offset) * T(position channels) * R(c1) * R(c2) * ... for one joint in one frame;
// `values` are that joint's channel values in channel order, `sin` and `cos` their sines and
// cosines (as angles in degrees). The rotation is only computed when `with_rotation` (a
// joint's own rotation moves its children, never itself).
Transform LocalTransform(const Joint& joint, const double* values, const double* sin,
                         const double* cos, bool with_rotation) {
  Transform local;
  local.translation[0] = joint.offset.x;
  local.translation[1] = joint.offset.y;
  local.translation[2] = joint.offset.z;
  for (size_t c = 0; c < joint.channels.size(); ++c) {
    const ChannelKind kind = joint.channels[c];
    if (kind == ChannelKind::kXPosition || kind == ChannelKind::kYPosition ||
        kind == ChannelKind::kZPosition) {
      local.translation[static_cast<int>(kind) - static_cast<int>(ChannelKind::kXPosition)] +=
          values[c];
    } else if (with_rotation) {
      RotateAbout(kind, sin[c], cos[c], local.rotation);
    }
  }
  return local;
}

// parent * local; the rotation only `with_rotation` (a leaf's world rotation is never used).
Transform Compose(const Transform& parent, const Transform& local, bool with_rotation) {
  Transform world;
  if (with_rotation) Multiply3(parent.rotation, local.rotation, world.rotation);
  for (int r = 0; r < 3; ++r) {
    world.translation[r] = parent.translation[r] + parent.rotation[3 * r] * local.translation[0] +
                           parent.rotation[3 * r + 1] * local.translation[1] +
                           parent.rotation[3 * r + 2] * local.translation[2];
  }
  return world;
}

}  // namespace

absl::StatusOr<std::vector<double>> ComputeWorldPositions(const Skeleton& skeleton,
                                                          absl::Span<const double> values,
                                                          int frame_count) {
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
  const size_t joint_count = joints.size();
  std::vector<bool> has_children(joint_count, false);
  for (const Joint& joint : joints) {
    if (joint.parent >= 0) has_children[joint.parent] = true;
  }
  std::vector<double> positions(static_cast<size_t>(frame_count) * joint_count * 3);
  std::vector<Transform> world(joint_count);  // this frame's world transforms
  // This frame's channels' sines and cosines, all at once (a vectorised loop). Not std::sin
  // and std::cos: their last bits differ between libms, and these bits reach the distances,
  // the tie rules and the response. Position channels get one too, unused: cheaper than
  // picking out the rotations.
  std::vector<double> sin(channel_count);
  std::vector<double> cos(channel_count);
  for (int f = 0; f < frame_count; ++f) {
    const double* frame = values.data() + static_cast<size_t>(f) * channel_count;
    SinCosDegrees(frame, channel_count, sin.data(), cos.data());
    double* out = positions.data() + static_cast<size_t>(f) * joint_count * 3;
    size_t first_channel = 0;
    for (size_t j = 0; j < joint_count; ++j) {
      const Joint& joint = joints[j];
      const Transform local =
          LocalTransform(joint, frame + first_channel, sin.data() + first_channel,
                         cos.data() + first_channel, has_children[j]);
      first_channel += joint.channels.size();
      // Parents precede children (ValidateSkeleton rule 2), so world[parent] is ready.
      world[j] = joint.parent < 0 ? local : Compose(world[joint.parent], local, has_children[j]);
      for (int c = 0; c < 3; ++c) out[3 * j + c] = world[j].translation[c];
    }
  }
  return positions;
}

absl::StatusOr<std::vector<double>> ComputeWorldPositions(const SkeletalClip& clip) {
  return ComputeWorldPositions(clip.skeleton, clip.values, clip.frame_count);
}

}  // namespace koma

// Skeleton and skeletal clip types shared by the BVH reader/writer, forward kinematics and
// the server. Plain data; Validate* functions check the numbered rules below.
#ifndef KOMA_CORE_SKELETON_H_
#define KOMA_CORE_SKELETON_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/container/inlined_vector.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma {

// One BVH channel. Positions are in the clip's length unit, rotations in degrees.
enum class ChannelKind : uint8_t {
  kXPosition,
  kYPosition,
  kZPosition,
  kXRotation,
  kYRotation,
  kZRotation,
};

// "Xposition" ... "Zrotation", exactly as BVH spells them (case-sensitive).
std::string_view ChannelName(ChannelKind kind);
// Inverse of ChannelName. INVALID_ARGUMENT naming `name` when it is not a BVH channel.
absl::StatusOr<ChannelKind> ParseChannelName(std::string_view name);

// A joint's channels, in the order their values appear in a frame. At most 6 in a valid
// skeleton (ValidateSkeleton rule), so they are held inline: a 31-joint request otherwise
// made 31 heap allocations per call just for these.
using ChannelList = absl::InlinedVector<ChannelKind, 6>;

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

struct Joint {
  std::string name;
  // Index of the parent in Skeleton::joints, -1 for a root. Parents come first.
  int parent = -1;
  // Rest offset from the parent joint, in the clip's length unit (BVH OFFSET).
  Vec3 offset;
  // Channels in the order their values appear in each frame (BVH CHANNELS).
  ChannelList channels;
  // BVH "End Site" offsets below this joint. They carry no channels and are not joints
  // for retiming; they are kept so a BVH file round-trips.
  std::vector<Vec3> end_sites;
};

// Joints in declaration (depth-first) order: ROOT and JOINT entries of a BVH file.
struct Skeleton {
  std::vector<Joint> joints;
};

// Total number of channels over all joints (values per frame).
int ChannelCount(const Skeleton& skeleton);

// Rules, each reported as INVALID_ARGUMENT with the path "joints[i].field" and the value:
//  1. at least one joint;
//  2. every parent is -1 or the index of an earlier joint (a parent that points to itself
//     or forms a loop is reported as a cycle; a later joint as out of order);
//  3. offsets and end-site offsets are finite;
//  4. at most 6 channels per joint, none repeated.
absl::Status ValidateSkeleton(const Skeleton& skeleton);

// A clip in BVH's channel form.
struct SkeletalClip {
  Skeleton skeleton;
  // Seconds per frame, kept exactly as read (BVH "Frame Time").
  double frame_time = 0.0;
  int frame_count = 0;
  // Frame-major channel values: frame_count x ChannelCount(skeleton).
  std::vector<double> values;
};

}  // namespace koma

#endif  // KOMA_CORE_SKELETON_H_

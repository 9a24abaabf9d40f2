#include "convert/skeletal_convert.h"

#include "absl/strings/str_cat.h"

namespace koma::convert {
namespace {

void SetVec3(const Vec3& in, v1::Vec3* out) {
  out->set_x(in.x);
  out->set_y(in.y);
  out->set_z(in.z);
}

FrameKind KindFromProto(int kind) {
  switch (kind) {
    case v1::DUPLICATE:
      return FrameKind::kDuplicate;
    case v1::HELD:
      return FrameKind::kHeld;
    default:
      return FrameKind::kOriginal;
  }
}

}  // namespace

v1::SkeletalMotion ToProto(const SkeletalClip& clip) {
  v1::SkeletalMotion motion;
  for (const Joint& joint : clip.skeleton.joints) {
    v1::Joint* out = motion.mutable_skeleton()->add_joints();
    out->set_name(joint.name);
    out->set_parent(joint.parent);
    SetVec3(joint.offset, out->mutable_offset());
    for (ChannelKind kind : joint.channels) out->add_channels(std::string(ChannelName(kind)));
    for (const Vec3& site : joint.end_sites) SetVec3(site, out->add_end_sites());
  }
  motion.set_frame_time(clip.frame_time);
  motion.set_frame_count(clip.frame_count);
  motion.mutable_channels()->mutable_values()->Add(clip.values.begin(), clip.values.end());
  return motion;
}

absl::StatusOr<SkeletalClip> ClipFromResponse(const v1::RetimeSkeletalResponse& response,
                                              const Skeleton& skeleton) {
  const v1::SkeletalMotion& motion = response.motion();
  SkeletalClip clip;
  clip.skeleton = skeleton;
  clip.frame_time = motion.frame_time();
  clip.frame_count = motion.frame_count();
  const int64_t expected = static_cast<int64_t>(clip.frame_count) * ChannelCount(skeleton);
  if (!motion.has_channels() || motion.channels().values_size() != expected) {
    return absl::InvalidArgumentError(absl::StrCat(
        "response motion.channels.values: expected ", expected, " values (", clip.frame_count,
        " frames x ", ChannelCount(skeleton), " channels), got ", motion.channels().values_size()));
  }
  clip.values.assign(motion.channels().values().begin(), motion.channels().values().end());
  return clip;
}

TimingMap TimingMapFromResponse(const v1::RetimeSkeletalResponse& response) {
  TimingMap map;
  map.source_frames.assign(response.source_frames().begin(), response.source_frames().end());
  map.kinds.reserve(response.kinds_size());
  for (int kind : response.kinds()) map.kinds.push_back(KindFromProto(kind));
  map.deleted.assign(response.deleted_frames().begin(), response.deleted_frames().end());
  map.hidden.assign(response.hidden_frames().begin(), response.hidden_frames().end());
  map.omissions_applied = response.omissions_applied();
  map.duplicates_applied = response.duplicates_applied();
  map.duplicates_skipped = response.duplicates_skipped();
  map.holds_applied = response.holds_applied();
  map.duplicates_omitted = response.duplicates_omitted();
  map.duplicates_held = response.duplicates_held();
  return map;
}

}  // namespace koma::convert

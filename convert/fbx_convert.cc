#include "convert/fbx_convert.h"

#include <vector>

#include "core/fbx_rig.h"

namespace koma::convert {

v1::SkeletalMotion FbxMotion(const formats::FbxTakeRig& rig, int64_t frames) {
  v1::SkeletalMotion motion;
  for (size_t i = 0; i < rig.names.size(); ++i) {
    v1::Joint* joint = motion.mutable_skeleton()->add_joints();
    joint->set_name(rig.names[i]);
    joint->set_parent(rig.rig.nodes[i].parent);
  }
  motion.set_frame_time(1.0 / rig.fps);
  motion.set_frame_count(static_cast<int32_t>(frames));
  const std::vector<double> positions = FbxNodePositions(rig.rig, rig.take.start, rig.fps, frames);
  motion.mutable_positions()->mutable_values()->Add(positions.begin(), positions.end());
  return motion;
}

}  // namespace koma::convert

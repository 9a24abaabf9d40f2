#include "convert/gltf_convert.h"

#include <vector>

#include "absl/strings/str_cat.h"
#include "core/gltf_animation.h"

namespace koma::convert {

std::string GltfJointName(const formats::GltfDocument& document, int node) {
  const std::string& name = document.node_names[static_cast<size_t>(node)];
  return name.empty() ? absl::StrCat("node", node) : name;
}

v1::Skeleton GltfSkeleton(const formats::GltfDocument& document) {
  v1::Skeleton skeleton;
  std::vector<int> joint_of(document.hierarchy.parent.size(), -1);
  for (size_t j = 0; j < document.joints.size(); ++j) {
    joint_of[static_cast<size_t>(document.joints[j])] = static_cast<int>(j);
  }
  for (int node : document.joints) {
    v1::Joint* joint = skeleton.add_joints();
    joint->set_name(GltfJointName(document, node));
    int parent = document.hierarchy.parent[static_cast<size_t>(node)];
    while (parent >= 0 && joint_of[static_cast<size_t>(parent)] < 0) {
      parent = document.hierarchy.parent[static_cast<size_t>(parent)];
    }
    joint->set_parent(parent < 0 ? -1 : joint_of[static_cast<size_t>(parent)]);
  }
  return skeleton;
}

v1::SkeletalMotion GltfMotion(const formats::GltfDocument& document, int animation, double fps,
                              int64_t frames) {
  const GltfClip& clip = document.animations[static_cast<size_t>(animation)].clip;
  v1::SkeletalMotion motion;
  *motion.mutable_skeleton() = GltfSkeleton(document);
  motion.set_frame_time(1.0 / fps);
  motion.set_frame_count(static_cast<int32_t>(frames));
  const std::vector<double> positions = GltfJointPositions(
      document.hierarchy, clip, document.joints, GltfClipStart(clip), fps, frames);
  motion.mutable_positions()->mutable_values()->Add(positions.begin(), positions.end());
  return motion;
}

}  // namespace koma::convert

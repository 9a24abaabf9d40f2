// A glTF animation as the positions-form SkeletalMotion RetimeSkeletal measures (shared by the
// server's glTF requests and the CLI's --report, so both see the same figures).
#ifndef KOMA_CONVERT_GLTF_CONVERT_H_
#define KOMA_CONVERT_GLTF_CONVERT_H_

#include <cstdint>
#include <string>

#include "formats/gltf.h"
#include "koma/v1/motion.pb.h"

namespace koma::convert {

// A joint's name: its node's, or "node<i>" when the node has none.
std::string GltfJointName(const formats::GltfDocument& document, int node);

// The document's joints (names; parent = the nearest ancestor that is a joint), no motion.
v1::Skeleton GltfSkeleton(const formats::GltfDocument& document);

// `animation` sampled at `fps` from its first key, `frames` frames: the joints' world
// positions (core/gltf_animation.h), frame_time 1 / fps.
v1::SkeletalMotion GltfMotion(const formats::GltfDocument& document, int animation, double fps,
                              int64_t frames);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_GLTF_CONVERT_H_

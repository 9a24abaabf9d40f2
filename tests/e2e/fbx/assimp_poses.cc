// Prints every node's world position in an FBX file's first animation as Debian's assimp reads
// it, with AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS off (on, assimp 5.2 applies Mixamo's
// pre-rotations and translation pivots twice, and splits each node into $AssimpFbx$ helpers),
// for tests that compare it with koma (tests/e2e/fbx/assimp_retimed_check.py):
//   assimp_poses FILE.fbx FRAMES FPS START_S
// JSON {"ticks_per_second", "channels", "poses": [{name: [x, y, z]}, ...]}: frames
// k = 0..FRAMES-1 at START_S + k / FPS seconds. assimp ignores key interpolation; between its
// keys this interpolates linearly (slerp for rotations), as its own evaluator does.
#include <assimp/anim.h>
#include <assimp/config.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "nlohmann/json.hpp"

namespace {

template <typename Key>
size_t Segment(const Key* keys, unsigned count, double time) {
  size_t k = 0;
  while (k + 1 < count && keys[k + 1].mTime <= time) ++k;
  return k;
}

aiVector3D VectorAt(const aiVectorKey* keys, unsigned count, double time, aiVector3D rest) {
  if (count == 0) return rest;
  if (time <= keys[0].mTime) return keys[0].mValue;
  const size_t k = Segment(keys, count, time);
  if (k + 1 >= count) return keys[count - 1].mValue;
  const double s = (time - keys[k].mTime) / (keys[k + 1].mTime - keys[k].mTime);
  return keys[k].mValue + (keys[k + 1].mValue - keys[k].mValue) * static_cast<ai_real>(s);
}

aiQuaternion RotationAt(const aiQuatKey* keys, unsigned count, double time, aiQuaternion rest) {
  if (count == 0) return rest;
  if (time <= keys[0].mTime) return keys[0].mValue;
  const size_t k = Segment(keys, count, time);
  if (k + 1 >= count) return keys[count - 1].mValue;
  const double s = (time - keys[k].mTime) / (keys[k + 1].mTime - keys[k].mTime);
  aiQuaternion out;
  aiQuaternion::Interpolate(out, keys[k].mValue, keys[k + 1].mValue, static_cast<ai_real>(s));
  return out.Normalize();
}

void Walk(const aiNode* node, const aiMatrix4x4& parent,
          const std::map<std::string, const aiNodeAnim*>& channels, double time,
          nlohmann::json& pose) {
  aiMatrix4x4 local = node->mTransformation;
  const auto it = channels.find(node->mName.C_Str());
  if (it != channels.end()) {
    const aiNodeAnim* c = it->second;
    aiVector3D rest_s, rest_t;
    aiQuaternion rest_r;
    node->mTransformation.Decompose(rest_s, rest_r, rest_t);
    const aiVector3D t = VectorAt(c->mPositionKeys, c->mNumPositionKeys, time, rest_t);
    const aiQuaternion r = RotationAt(c->mRotationKeys, c->mNumRotationKeys, time, rest_r);
    const aiVector3D s = VectorAt(c->mScalingKeys, c->mNumScalingKeys, time, rest_s);
    local = aiMatrix4x4(s, r, t);
  }
  const aiMatrix4x4 world = parent * local;
  pose[node->mName.C_Str()] = {world.a4, world.b4, world.c4};
  for (unsigned i = 0; i < node->mNumChildren; ++i) {
    Walk(node->mChildren[i], world, channels, time, pose);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: assimp_poses FILE.fbx FRAMES FPS START_S\n";
    return 2;
  }
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  const aiScene* scene = importer.ReadFile(argv[1], 0);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    std::cerr << argv[1] << ": assimp: " << importer.GetErrorString() << "\n";
    return 1;
  }
  if (scene->mNumAnimations == 0) {
    std::cerr << argv[1] << ": assimp finds no animation\n";
    return 1;
  }
  const aiAnimation* animation = scene->mAnimations[0];
  std::map<std::string, const aiNodeAnim*> channels;
  for (unsigned i = 0; i < animation->mNumChannels; ++i) {
    channels[animation->mChannels[i]->mNodeName.C_Str()] = animation->mChannels[i];
  }
  const long frames = std::stol(argv[2]);
  const double fps = std::stod(argv[3]);
  const double start_s = std::stod(argv[4]);
  // assimp's FBX key times are in the file's frames (mTicksPerSecond its frame rate), from
  // time 0 (not from the take's start).
  const double ticks_per_second =
      animation->mTicksPerSecond > 0 ? animation->mTicksPerSecond : 25.0;
  nlohmann::json out;
  out["ticks_per_second"] = ticks_per_second;
  out["channels"] = animation->mNumChannels;
  nlohmann::json poses = nlohmann::json::array();
  for (long k = 0; k < frames; ++k) {
    const double time = (start_s + static_cast<double>(k) / fps) * ticks_per_second;
    nlohmann::json pose = nlohmann::json::object();
    Walk(scene->mRootNode, aiMatrix4x4(), channels, time, pose);
    poses.push_back(pose);
  }
  out["poses"] = poses;
  std::cout << out.dump() << "\n";
  return 0;
}

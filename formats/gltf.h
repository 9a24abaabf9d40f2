// glTF 2.0 files (.glb, and .gltf with embedded data: buffers; VRM .vrm and VRM Animation
// .vrma are glTF files) <-> the plain types of core/gltf_animation.h, keeping the rest of the
// file for writing it back (docs/formats.md, "glTF 2.0 and VRM").
//
// Reading goes through Debian's tinygltf (the structure: nodes, skins, animations, accessors),
// with every accessor an animation uses decoded and checked here. Writing edits the file's own
// JSON (key order, extensions and extras as they were) and its binary buffers.
#ifndef KOMA_FORMATS_GLTF_H_
#define KOMA_FORMATS_GLTF_H_

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "core/gltf_animation.h"

namespace koma::formats {

// Sizes a file may have before it is refused, naming the limit: INVALID_ARGUMENT for nodes,
// RESOURCE_EXHAUSTED for animations and keys (the work they cost).
struct GltfReadLimits {
  int64_t max_nodes = 65536;      // nodes[] entries
  int64_t max_animations = 4096;  // animations[] entries
  int64_t max_keys = 20'000'000;  // key times over all animation samplers
};

struct GltfAnimation {
  std::string name;  // may be empty
  GltfClip clip;
};

struct GltfDocument {
  bool binary = false;  // a GLB container (.glb, .vrm, .vrma); else .gltf JSON text
  // The JSON document as read, keys in file order: the writer edits a copy.
  nlohmann::ordered_json json;
  // Every buffer's bytes (the GLB BIN chunk, or a data: URI decoded), byteLength long.
  std::vector<std::string> buffers;
  // Every node: parent, rest TRS; order = every node, parents first (depth-first from the
  // roots in index order).
  GltfHierarchy hierarchy;
  std::vector<std::string> node_names;  // "" when unnamed
  // The nodes whose positions measure speed, in hierarchy order: the joints of every skin, or
  // every node when the file has no skin (a VRM Animation's humanoid bones).
  std::vector<int> joints;
  std::vector<GltfAnimation> animations;
};

// Reads a .glb (by its "glTF" magic) or a .gltf (JSON text). INVALID_ARGUMENT naming the JSON
// path or the GLB chunk: a truncated or malformed container, invalid JSON, a buffer or image
// with an external uri ("a .gltf with external files": only one file travels), accessors and
// buffer views outside their buffers, byteStride shorter than an element, a node with two
// parents or in a cycle, out-of-range indices, animation keys that are not finite or not in
// time order, sampler outputs of the wrong count, type or component type, sparse animation
// accessors, and the limits above.
absl::StatusOr<GltfDocument> ReadGltf(std::string_view bytes, const GltfReadLimits& limits = {});

// The keys that replace one animation's samplers.
struct GltfAnimationKeys {
  int animation = 0;    // index into GltfDocument::animations
  bool linear = false;  // LINEAR samplers (one key per output frame); else STEP
  // Key times, seconds, increasing. Written as 32-bit floats rounded down, so a player
  // sampling at exactly a frame's time sees that frame's key, never the one before.
  std::vector<double> times;
  // Per channel of the animation, in its order: times.size() x the channel's width values.
  std::vector<std::vector<double>> values;
};

// The document with each listed animation's samplers replaced by the given keys (one sampler
// per channel, every channel sharing one time accessor), or with `keep_original` a new
// animation "<name>.anime" added beside each instead. Everything else is kept: nodes, meshes,
// skins, materials, images, extensions and extras, key order. Accessors and buffer views only
// the replaced samplers used are removed (indices after them renumbered in meshes, skins,
// animations, images and EXT_mesh_gpu_instancing / KHR_draco_mesh_compression), and their
// bytes dropped from the buffer. Same container as read: GLB, or .gltf with data: URIs.
absl::StatusOr<std::string> WriteGltf(const GltfDocument& document,
                                      const std::vector<GltfAnimationKeys>& keys,
                                      bool keep_original);

// "glTF" magic at the start: a GLB container.
bool IsGlb(std::string_view bytes);

// What a glTF file's JSON document (and tinygltf's model of it) grows with: the bytes of its
// JSON (a GLB's JSON chunk, as its header states it) outside strings of 256 bytes or more,
// which are data: URIs and base64 buffers, one value each however long.
int64_t GltfJsonStructureBytes(std::string_view file);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_GLTF_H_

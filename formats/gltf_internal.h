// Shared by gltf_reader.cc and gltf_container.cc: the GLB container, the JSON checks made before
// tinygltf sees a file, and checked accessor decoding.
#ifndef KOMA_FORMATS_GLTF_INTERNAL_H_
#define KOMA_FORMATS_GLTF_INTERNAL_H_

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "formats/gltf.h"

namespace koma::formats {

inline constexpr uint32_t kGlbMagic = 0x46546C67;      // "glTF"
inline constexpr uint32_t kGlbJsonChunk = 0x4E4F534A;  // "JSON"
inline constexpr uint32_t kGlbBinChunk = 0x004E4942;   // "BIN\0"

struct GlbChunks {
  std::string_view json;
  std::string_view bin;  // empty when the file has no BIN chunk
};

// The GLB header and its first two chunks (JSON, then an optional BIN), every length checked
// against the bytes there are: INVALID_ARGUMENT naming the chunk ("GLB chunk 1 (BIN): ...").
absl::StatusOr<GlbChunks> SplitGlb(std::string_view bytes);

// A GLB container around `json` (padded with spaces) and `bin` (padded with zeros; no BIN
// chunk when empty).
std::string JoinGlb(std::string_view json, std::string_view bin);

// Checks on the JSON before tinygltf parses it, so the messages name the JSON path: the node
// limit, bufferView byteStride within glTF's 4..252 (a multiple of 4).
absl::Status CheckGltfJson(const nlohmann::ordered_json& json, const GltfReadLimits& limits);

struct AccessorData {
  std::vector<double> values;  // count x components, normalized integers as glTF maps them
  int components = 0;
  int component_type = 0;
  bool normalized = false;
};

// Accessor `index` (used at JSON path `path`) decoded, after checking the accessor, its buffer
// view and buffer exist and the elements lie inside the view (with its byteStride, which must
// not be shorter than an element). `values_left` counts down the file's value budget.
absl::StatusOr<AccessorData> ReadAccessor(const tinygltf::Model& model, int index,
                                          const std::string& path, int64_t& values_left);

// RFC 4648 base64, for data: URIs.
std::string Base64(std::string_view bytes);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_GLTF_INTERNAL_H_

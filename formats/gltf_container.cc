// The GLB container, JSON pre-checks, accessor decoding and base64 (formats/gltf_internal.h).
#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "absl/strings/str_cat.h"
#include "formats/gltf_internal.h"

namespace koma::formats {
namespace {

uint32_t ReadU32(std::string_view bytes, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
  return v;
}

void AppendU32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

absl::Status Invalid(absl::string_view path, absl::string_view message) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", message));
}

const char* TypeName(int components) {
  switch (components) {
    case 1:
      return "SCALAR";
    case 2:
      return "VEC2";
    case 3:
      return "VEC3";
    case 4:
      return "VEC4";
  }
  return "MAT";
}

double Component(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<int8_t>(p[0]);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
  }
  return 0;
}

}  // namespace

absl::StatusOr<GlbChunks> SplitGlb(std::string_view bytes) {
  if (bytes.size() < 12) {
    return absl::InvalidArgumentError(
        absl::StrCat("GLB header: ", bytes.size(), " bytes, a GLB header needs 12"));
  }
  if (ReadU32(bytes, 0) != kGlbMagic)
    return absl::InvalidArgumentError("GLB header: no glTF magic");
  if (const uint32_t version = ReadU32(bytes, 4); version != 2) {
    return absl::InvalidArgumentError(
        absl::StrCat("GLB header: version ", version, ", koma reads glTF 2"));
  }
  const uint32_t length = ReadU32(bytes, 8);
  if (length != bytes.size()) {
    return absl::InvalidArgumentError(absl::StrCat("GLB header: length ", length,
                                                   " but the file has ", bytes.size(), " bytes",
                                                   length > bytes.size() ? " (truncated)" : ""));
  }
  GlbChunks chunks;
  size_t at = 12;
  for (int chunk = 0; chunk < 2 && at < bytes.size(); ++chunk) {
    const char* name = chunk == 0 ? "JSON" : "BIN";
    const std::string where = absl::StrCat("GLB chunk ", chunk, " (", name, ")");
    if (bytes.size() - at < 8) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": ", bytes.size() - at, " bytes left, a chunk header needs 8"));
    }
    const uint32_t chunk_length = ReadU32(bytes, at);
    const uint32_t type = ReadU32(bytes, at + 4);
    if (type != (chunk == 0 ? kGlbJsonChunk : kGlbBinChunk)) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": type 0x", absl::Hex(type), " where ", name, " must be"));
    }
    at += 8;
    if (chunk_length > bytes.size() - at) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": ", chunk_length, " bytes declared, ",
                                                     bytes.size() - at,
                                                     " left in the file (truncated)"));
    }
    (chunk == 0 ? chunks.json : chunks.bin) = bytes.substr(at, chunk_length);
    at += chunk_length;
  }
  if (at == 12) return absl::InvalidArgumentError("GLB chunk 0 (JSON): missing");
  return chunks;
}

std::string JoinGlb(std::string_view json, std::string_view bin) {
  const size_t json_padded = (json.size() + 3) / 4 * 4;
  const size_t bin_padded = (bin.size() + 3) / 4 * 4;
  const size_t total = 12 + 8 + json_padded + (bin.empty() ? 0 : 8 + bin_padded);
  std::string out;
  out.reserve(total);
  AppendU32(out, kGlbMagic);
  AppendU32(out, 2);
  AppendU32(out, static_cast<uint32_t>(total));
  AppendU32(out, static_cast<uint32_t>(json_padded));
  AppendU32(out, kGlbJsonChunk);
  out.append(json);
  out.append(json_padded - json.size(), ' ');
  if (!bin.empty()) {
    AppendU32(out, static_cast<uint32_t>(bin_padded));
    AppendU32(out, kGlbBinChunk);
    out.append(bin);
    out.append(bin_padded - bin.size(), '\0');
  }
  return out;
}

int64_t GltfJsonStructureBytes(std::string_view file) {
  constexpr size_t kLongString = 256;  // data: URIs and base64 buffers are no longer
  std::string_view json = file;
  if (file.size() >= 20 && IsGlb(file)) {
    json = file.substr(20, std::min<size_t>(ReadU32(file, 12), file.size() - 20));
  }
  int64_t structure = 0;
  size_t i = 0;
  while (i < json.size()) {
    if (json[i] != '"') {
      ++structure;
      ++i;
      continue;
    }
    size_t end = i + 1;
    while (end < json.size() && json[end] != '"') end += json[end] == '\\' ? 2 : 1;
    const size_t length = std::min(end + 1, json.size()) - i;
    if (length < kLongString) structure += static_cast<int64_t>(length);
    i += length;
  }
  return structure;
}

absl::Status CheckGltfJson(const nlohmann::ordered_json& json, const GltfReadLimits& limits) {
  if (const auto nodes = json.find("nodes"); nodes != json.end() && nodes->is_array()) {
    if (static_cast<int64_t>(nodes->size()) > limits.max_nodes) {
      return Invalid("nodes",
                     absl::StrCat(nodes->size(), " nodes exceeds the limit of ", limits.max_nodes));
    }
  }
  if (const auto animations = json.find("animations");
      animations != json.end() && animations->is_array() &&
      static_cast<int64_t>(animations->size()) > limits.max_animations) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "animations: ", animations->size(),
        " animations exceeds the server limit --max_gltf_animations=", limits.max_animations));
  }
  if (const auto views = json.find("bufferViews"); views != json.end() && views->is_array()) {
    for (size_t v = 0; v < views->size(); ++v) {
      const auto& view = (*views)[v];
      if (!view.is_object()) continue;
      const auto stride = view.find("byteStride");
      if (stride == view.end()) continue;
      if (!stride->is_number_integer() || stride->get<int64_t>() < 4 ||
          stride->get<int64_t>() > 252 || stride->get<int64_t>() % 4 != 0) {
        return Invalid(absl::StrCat("bufferViews[", v, "].byteStride"),
                       absl::StrCat(stride->dump(), " is not a multiple of 4 in 4..252"));
      }
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<AccessorData> ReadAccessor(const tinygltf::Model& model, int index,
                                          const std::string& path, int64_t& values_left) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    return Invalid(path, absl::StrCat("accessor ", index, " does not exist (",
                                      model.accessors.size(), " accessors)"));
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string at = absl::StrCat(path, " (accessors[", index, "])");
  if (accessor.sparse.isSparse) {
    return Invalid(at, "is sparse; koma reads dense animation accessors");
  }
  const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
  if (components < 1 || components > 4 || size <= 0) {
    return Invalid(at, "not a SCALAR or VEC2..4 accessor of a glTF component type");
  }
  if (accessor.bufferView < 0 ||
      static_cast<size_t>(accessor.bufferView) >= model.bufferViews.size()) {
    return Invalid(at, absl::StrCat("bufferView ", accessor.bufferView, " does not exist (",
                                    model.bufferViews.size(), " buffer views)"));
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(accessor.bufferView)];
  const std::string view_path = absl::StrCat("bufferViews[", accessor.bufferView, "]");
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size()) {
    return Invalid(view_path + ".buffer", absl::StrCat("buffer ", view.buffer, " does not exist (",
                                                       model.buffers.size(), " buffers)"));
  }
  const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
    return Invalid(
        view_path,
        absl::StrCat("bytes ", view.byteOffset, " .. ", view.byteOffset + view.byteLength,
                     " pass the end of buffers[", view.buffer, "] (", data.size(), " bytes)"));
  }
  const size_t element = static_cast<size_t>(components) * static_cast<size_t>(size);
  const size_t stride = view.byteStride == 0 ? element : view.byteStride;
  if (stride < element) {
    return Invalid(view_path + ".byteStride",
                   absl::StrCat(stride, " is shorter than the ", TypeName(components),
                                " element of accessors[", index, "] (", element, " bytes)"));
  }
  const size_t count = accessor.count;
  if (count > 0) {
    const bool fits = accessor.byteOffset <= view.byteLength &&
                      (count - 1) <= (view.byteLength - accessor.byteOffset) / stride &&
                      accessor.byteOffset + (count - 1) * stride + element <= view.byteLength;
    if (!fits) {
      return Invalid(at,
                     absl::StrCat(count, " ", TypeName(components), " elements from byte ",
                                  accessor.byteOffset, " with stride ", stride, " pass the end of ",
                                  view_path, " (", view.byteLength, " bytes)"));
    }
  }
  const int64_t wanted = static_cast<int64_t>(count) * components;
  if (wanted > values_left) {
    return Invalid(at, "the animations hold more values than the limit (--max_values)");
  }
  values_left -= wanted;
  AccessorData out;
  out.components = components;
  out.component_type = accessor.componentType;
  out.normalized = accessor.normalized;
  out.values.resize(count * static_cast<size_t>(components));
  const unsigned char* base = data.data() + view.byteOffset + accessor.byteOffset;
  for (size_t i = 0; i < count; ++i) {
    const unsigned char* element_bytes = base + i * stride;
    for (int c = 0; c < components; ++c) {
      out.values[i * static_cast<size_t>(components) + static_cast<size_t>(c)] =
          Component(element_bytes + c * size, accessor.componentType, accessor.normalized);
    }
  }
  return out;
}

std::string Base64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace koma::formats

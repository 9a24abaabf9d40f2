// ReadGltf: the GLB container and the JSON checked here, the structure parsed by tinygltf, then
// every animation accessor decoded and checked with its JSON path.
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/error_text.h"
#include "formats/gltf.h"
#include "formats/gltf_internal.h"
#include "formats/json_text.h"

namespace koma::formats {
namespace {

using Json = nlohmann::ordered_json;

// JSON deeper than this is refused before it is parsed (tinygltf and nlohmann recurse).
constexpr int kMaxJsonDepth = 64;

absl::Status Invalid(absl::string_view path, absl::string_view message) {
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", message));
}

// The JSON of a .gltf file or a GLB's JSON chunk; errors in koma's words with the byte offset
// (formats/json_text.h), an empty file named as such.
absl::StatusOr<Json> ParseJson(std::string_view text) {
  if (text.empty()) {
    return absl::InvalidArgumentError(
        "the file is empty: expected a GLB (starting \"glTF\") or a .gltf's JSON");
  }
  KOMA_ASSIGN_OR_RETURN(Json json, ParseJsonTextWithin(text, kMaxJsonDepth));
  if (!json.is_object()) return absl::InvalidArgumentError("the JSON is not an object");
  return json;
}

// What is wrong with a data: URI's payload ("" when nothing is): base64 after ";base64,", of
// at least `min_bytes` bytes once decoded (a buffer's byteLength; 0 for images). Checked here
// so that the message names the field and the position, instead of tinygltf's, which quotes
// the whole URI (megabytes).
std::string DataUriProblem(const std::string& uri, int64_t min_bytes) {
  const size_t marker = uri.find(";base64,");
  if (marker == std::string::npos) {
    return absl::StrCat("a data: URI of ", uri.size(),
                        " characters without \";base64,\": glTF embeds data as base64");
  }
  const size_t start = marker + 8;
  const size_t length = uri.size() - start;
  size_t padding = 0;
  for (size_t i = start; i < uri.size(); ++i) {
    const char c = uri[i];
    const bool base64 = absl::ascii_isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/';
    if (c == '=' && i + 2 >= uri.size()) {
      ++padding;
    } else if (!base64 || padding > 0) {
      return absl::StrCat("character ", i - start, " of its base64 data (of ", length,
                          ") is not base64: ", QuoteForError(std::string(1, c)));
    }
  }
  // Unpadded base64 (which some exporters write) is read as tinygltf reads it; a remainder of
  // one character cannot be base64 at all.
  if (length % 4 == 1) {
    return absl::StrCat("its base64 data is ", length,
                        " characters, one more than whole bytes (cut short?)");
  }
  const int64_t decoded = static_cast<int64_t>((length - padding) * 3 / 4);
  if (decoded < min_bytes) {
    return absl::StrCat("its base64 data decodes to ", decoded,
                        " bytes, fewer than its byteLength ", min_bytes);
  }
  return "";
}

// Refuses what needs files beside this one: buffers and images with a uri that is not data:.
absl::Status CheckSelfContained(const Json& json, bool binary) {
  for (const char* array : {"buffers", "images"}) {
    const auto it = json.find(array);
    if (it == json.end() || !it->is_array()) continue;
    for (size_t i = 0; i < it->size(); ++i) {
      const Json& entry = (*it)[i];
      if (!entry.is_object()) continue;
      const auto uri = entry.find("uri");
      if (uri == entry.end()) {
        if (std::string(array) == "buffers" && !(binary && i == 0)) {
          return Invalid(absl::StrCat(array, "[", i, "]"),
                         "has no uri (only a GLB's first buffer is its BIN chunk)");
        }
        continue;
      }
      if (!uri->is_string()) return Invalid(absl::StrCat(array, "[", i, "].uri"), "not a string");
      const std::string& value = uri->get_ref<const std::string&>();
      if (!absl::StartsWith(value, "data:")) {
        return Invalid(absl::StrCat(array, "[", i, "].uri"),
                       absl::StrCat(QuoteForError(value),
                                    " is an external file; koma reads self-contained glTF "
                                    "(a .glb, or a .gltf with embedded data: URIs), since only "
                                    "one file travels"));
      }
      const auto length = entry.find("byteLength");
      const int64_t min_bytes =
          std::string(array) == "buffers" && length != entry.end() && length->is_number_unsigned()
              ? length->get<int64_t>()
              : 0;
      if (const std::string problem = DataUriProblem(value, min_bytes); !problem.empty()) {
        return Invalid(absl::StrCat(array, "[", i, "].uri"), problem);
      }
    }
  }
  return absl::OkStatus();
}

// tinygltf gets no file system: every file it asks for is refused.
tinygltf::FsCallbacks NoFiles() {
  tinygltf::FsCallbacks fs{};
  fs.FileExists = [](const std::string&, void*) { return false; };
  fs.ExpandFilePath = [](const std::string& path, void*) { return path; };
  fs.ReadWholeFile = [](std::vector<unsigned char>*, std::string* err, const std::string& path,
                        void*) {
    if (err != nullptr) *err = absl::StrCat("external file ", path, " refused");
    return false;
  };
  fs.WriteWholeFile = [](std::string*, const std::string&, const std::vector<unsigned char>&,
                         void*) { return false; };
  fs.user_data = nullptr;
  return fs;
}

// Images are kept as bytes, never decoded.
bool KeepImageBytes(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                    const unsigned char*, int, void*) {
  return true;
}

std::string FirstLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (text.size() > 300) text = text.substr(0, 300) + "...";
  return text;
}

absl::StatusOr<tinygltf::Model> LoadModel(std::string_view bytes, bool binary) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&KeepImageBytes, nullptr);
  loader.SetFsCallbacks(NoFiles());
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), "")
             : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()), "");
  if (!ok) {
    return absl::InvalidArgumentError(
        absl::StrCat("tinygltf: ", FirstLine(err.empty() ? warn : err)));
  }
  return model;
}

// The node tree: parents from children lists, refusing a second parent and cycles; the order
// is depth-first from the roots, iteratively (100,000 nested nodes must not overflow a stack).
absl::Status BuildHierarchy(const tinygltf::Model& model, GltfDocument& document) {
  const size_t n = model.nodes.size();
  GltfHierarchy& h = document.hierarchy;
  h.parent.assign(n, -1);
  h.rest.resize(n);
  document.node_names.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const tinygltf::Node& node = model.nodes[i];
    document.node_names[i] = node.name;
    for (size_t c = 0; c < node.children.size(); ++c) {
      const int child = node.children[c];
      const std::string path = absl::StrCat("nodes[", i, "].children[", c, "]");
      if (child < 0 || static_cast<size_t>(child) >= n) {
        return Invalid(path, absl::StrCat("node ", child, " does not exist (", n, " nodes)"));
      }
      if (static_cast<size_t>(child) == i) return Invalid(path, "a node cannot be its own child");
      if (h.parent[static_cast<size_t>(child)] >= 0) {
        return Invalid(path, absl::StrCat("node ", child, " is already a child of node ",
                                          h.parent[static_cast<size_t>(child)],
                                          " (a node has at most one parent)"));
      }
      h.parent[static_cast<size_t>(child)] = static_cast<int>(i);
    }
    GltfNodeTransform& rest = h.rest[i];
    const std::string path = absl::StrCat("nodes[", i, "]");
    auto copy = [&](const std::vector<double>& from, double* to, size_t size,
                    const char* field) -> absl::Status {
      if (from.empty()) return absl::OkStatus();
      if (from.size() != size) {
        return Invalid(absl::StrCat(path, ".", field),
                       absl::StrCat(from.size(), " numbers, expected ", size));
      }
      for (size_t k = 0; k < size; ++k) {
        if (!std::isfinite(from[k])) {
          return Invalid(absl::StrCat(path, ".", field, "[", k, "]"), "not a finite number");
        }
        to[k] = from[k];
      }
      return absl::OkStatus();
    };
    KOMA_RETURN_IF_ERROR(copy(node.translation, rest.translation.data(), 3, "translation"));
    KOMA_RETURN_IF_ERROR(copy(node.rotation, rest.rotation.data(), 4, "rotation"));
    KOMA_RETURN_IF_ERROR(copy(node.scale, rest.scale.data(), 3, "scale"));
    KOMA_RETURN_IF_ERROR(copy(node.matrix, rest.matrix.data(), 16, "matrix"));
    rest.has_matrix = !node.matrix.empty();
  }
  // Depth-first from each root in index order; a node never reached sits on a cycle.
  h.order.clear();
  h.order.reserve(n);
  std::vector<int> stack;
  for (size_t root = 0; root < n; ++root) {
    if (h.parent[root] >= 0) continue;
    stack.push_back(static_cast<int>(root));
    while (!stack.empty()) {
      const int node = stack.back();
      stack.pop_back();
      h.order.push_back(node);
      const std::vector<int>& children = model.nodes[static_cast<size_t>(node)].children;
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(*it);
    }
  }
  if (h.order.size() != n) {
    std::vector<bool> reached(n, false);
    for (int node : h.order) reached[static_cast<size_t>(node)] = true;
    for (size_t i = 0; i < n; ++i) {
      if (!reached[i]) {
        return Invalid(absl::StrCat("nodes[", i, "]"),
                       "is its own ancestor (the node graph has a cycle)");
      }
    }
  }
  return absl::OkStatus();
}

absl::Status FindJoints(const tinygltf::Model& model, GltfDocument& document) {
  const size_t n = model.nodes.size();
  std::vector<bool> is_joint(n, model.skins.empty());
  for (size_t s = 0; s < model.skins.size(); ++s) {
    const std::vector<int>& joints = model.skins[s].joints;
    for (size_t j = 0; j < joints.size(); ++j) {
      if (joints[j] < 0 || static_cast<size_t>(joints[j]) >= n) {
        return Invalid(absl::StrCat("skins[", s, "].joints[", j, "]"),
                       absl::StrCat("node ", joints[j], " does not exist (", n, " nodes)"));
      }
      is_joint[static_cast<size_t>(joints[j])] = true;
    }
  }
  for (int node : document.hierarchy.order) {
    if (is_joint[static_cast<size_t>(node)]) document.joints.push_back(node);
  }
  return absl::OkStatus();
}

absl::StatusOr<GltfInterpolation> ParseInterpolation(const std::string& text,
                                                     const std::string& path) {
  if (text == "LINEAR") return GltfInterpolation::kLinear;
  if (text == "STEP") return GltfInterpolation::kStep;
  if (text == "CUBICSPLINE") return GltfInterpolation::kCubicSpline;
  return Invalid(path, absl::StrCat(QuoteForError(text), " is not LINEAR, STEP or CUBICSPLINE"));
}

absl::StatusOr<GltfPath> ParsePath(const std::string& text, const std::string& path) {
  if (text == "translation") return GltfPath::kTranslation;
  if (text == "rotation") return GltfPath::kRotation;
  if (text == "scale") return GltfPath::kScale;
  if (text == "weights") return GltfPath::kWeights;
  return Invalid(
      path, absl::StrCat(QuoteForError(text), " is not translation, rotation, scale or weights"));
}

// tinygltf skips some malformed entries instead of failing (a channel without "sampler", say),
// which would shift every index after them against the JSON the writer edits: the counts must
// agree, entry for entry.
size_t JsonSize(const Json& json, const char* key) {
  const auto it = json.find(key);
  return it != json.end() && it->is_array() ? it->size() : 0;
}

absl::Status CheckCount(absl::string_view path, size_t in_json, size_t read) {
  if (in_json == read) return absl::OkStatus();
  return Invalid(path, absl::StrCat(in_json, " entries, of which tinygltf read ", read,
                                    ": an entry is malformed (a required member missing or of "
                                    "the wrong type)"));
}

absl::Status CheckCounts(const Json& json, const tinygltf::Model& model) {
  for (const char* key : {"accessors", "animations", "bufferViews", "buffers", "images", "meshes",
                          "nodes", "skins", "scenes", "materials", "textures"}) {
    const auto it = json.find(key);
    if (it != json.end() && !it->is_array()) return Invalid(key, "not an array");
  }
  KOMA_RETURN_IF_ERROR(
      CheckCount("accessors", JsonSize(json, "accessors"), model.accessors.size()));
  KOMA_RETURN_IF_ERROR(
      CheckCount("animations", JsonSize(json, "animations"), model.animations.size()));
  KOMA_RETURN_IF_ERROR(
      CheckCount("bufferViews", JsonSize(json, "bufferViews"), model.bufferViews.size()));
  KOMA_RETURN_IF_ERROR(CheckCount("buffers", JsonSize(json, "buffers"), model.buffers.size()));
  KOMA_RETURN_IF_ERROR(CheckCount("images", JsonSize(json, "images"), model.images.size()));
  KOMA_RETURN_IF_ERROR(CheckCount("meshes", JsonSize(json, "meshes"), model.meshes.size()));
  KOMA_RETURN_IF_ERROR(CheckCount("nodes", JsonSize(json, "nodes"), model.nodes.size()));
  KOMA_RETURN_IF_ERROR(CheckCount("skins", JsonSize(json, "skins"), model.skins.size()));
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const Json& animation = json["animations"][a];
    if (!animation.is_object())
      return Invalid(absl::StrCat("animations[", a, "]"), "not an object");
    const std::string path = absl::StrCat("animations[", a, "]");
    KOMA_RETURN_IF_ERROR(CheckCount(path + ".channels", JsonSize(animation, "channels"),
                                    model.animations[a].channels.size()));
    KOMA_RETURN_IF_ERROR(CheckCount(path + ".samplers", JsonSize(animation, "samplers"),
                                    model.animations[a].samplers.size()));
    // The glTF schema: an animation has at least one channel and one sampler (minItems 1).
    if (model.animations[a].channels.empty()) {
      return Invalid(path + ".channels", "empty: a glTF animation has at least one channel");
    }
    if (model.animations[a].samplers.empty()) {
      return Invalid(path + ".samplers", "empty: a glTF animation has at least one sampler");
    }
  }
  for (size_t s = 0; s < model.skins.size(); ++s) {
    const Json& skin = json["skins"][s];
    if (!skin.is_object()) return Invalid(absl::StrCat("skins[", s, "]"), "not an object");
    KOMA_RETURN_IF_ERROR(CheckCount(absl::StrCat("skins[", s, "].joints"), JsonSize(skin, "joints"),
                                    model.skins[s].joints.size()));
  }
  return absl::OkStatus();
}

absl::Status ReadAnimation(const tinygltf::Model& model, size_t index, int64_t& keys_left,
                           GltfAnimation& out) {
  const tinygltf::Animation& animation = model.animations[index];
  const std::string base = absl::StrCat("animations[", index, "]");
  out.name = animation.name;
  out.clip.samplers.resize(animation.samplers.size());
  std::vector<bool> sampler_used(animation.samplers.size(), false);
  std::vector<int> sampler_width(animation.samplers.size(), 0);
  std::vector<bool> sampler_rotation(animation.samplers.size(), false);
  for (size_t c = 0; c < animation.channels.size(); ++c) {
    const tinygltf::AnimationChannel& channel = animation.channels[c];
    const std::string path = absl::StrCat(base, ".channels[", c, "]");
    GltfChannel parsed;
    if (channel.sampler < 0 || static_cast<size_t>(channel.sampler) >= animation.samplers.size()) {
      return Invalid(path + ".sampler",
                     absl::StrCat("sampler ", channel.sampler, " does not exist (",
                                  animation.samplers.size(), " samplers)"));
    }
    if (channel.target_node < 0 || static_cast<size_t>(channel.target_node) >= model.nodes.size()) {
      return Invalid(path + ".target.node",
                     absl::StrCat("node ", channel.target_node, " does not exist (",
                                  model.nodes.size(), " nodes)"));
    }
    KOMA_ASSIGN_OR_RETURN(parsed.path, ParsePath(channel.target_path, path + ".target.path"));
    parsed.node = channel.target_node;
    parsed.sampler = channel.sampler;
    if (parsed.path != GltfPath::kWeights &&
        !model.nodes[static_cast<size_t>(parsed.node)].matrix.empty()) {
      return Invalid(path + ".target.node", absl::StrCat("node ", parsed.node,
                                                         " has a matrix; glTF animates only "
                                                         "nodes given as translation, rotation "
                                                         "and scale"));
    }
    const size_t s = static_cast<size_t>(channel.sampler);
    const int width = parsed.path == GltfPath::kRotation  ? 4
                      : parsed.path == GltfPath::kWeights ? 0
                                                          : 3;
    if (sampler_used[s] && sampler_width[s] != width) {
      return Invalid(path + ".sampler",
                     absl::StrCat("sampler ", s, " also drives a channel of another kind"));
    }
    sampler_used[s] = true;
    sampler_width[s] = width;
    sampler_rotation[s] = parsed.path == GltfPath::kRotation;
    out.clip.channels.push_back(parsed);
  }
  for (size_t s = 0; s < animation.samplers.size(); ++s) {
    const tinygltf::AnimationSampler& sampler = animation.samplers[s];
    const std::string path = absl::StrCat(base, ".samplers[", s, "]");
    GltfSampler& parsed = out.clip.samplers[s];
    KOMA_ASSIGN_OR_RETURN(parsed.interpolation,
                          ParseInterpolation(sampler.interpolation, path + ".interpolation"));
    KOMA_ASSIGN_OR_RETURN(const AccessorData input,
                          ReadAccessor(model, sampler.input, path + ".input", keys_left));
    if (input.components != 1 || input.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) {
      return Invalid(path + ".input", "key times must be a SCALAR FLOAT accessor");
    }
    if (input.values.empty()) return Invalid(path + ".input", "has no keys");
    for (size_t k = 0; k < input.values.size(); ++k) {
      if (!std::isfinite(input.values[k])) {
        return Invalid(path + ".input", absl::StrCat("key ", k, " is not a finite time"));
      }
      if (input.values[k] < 0) {  // the Khronos validator's ACCESSOR_ANIMATION_INPUT_NEGATIVE
        return Invalid(path + ".input", absl::StrCat("key ", k, " is at ", input.values[k],
                                                     " s: glTF key times are >= 0"));
      }
      if (k > 0 && input.values[k] < input.values[k - 1]) {
        return Invalid(path + ".input",
                       absl::StrCat("key ", k, " (", input.values[k], " s) is before key ", k - 1,
                                    " (", input.values[k - 1], " s): key times must increase"));
      }
    }
    parsed.times = input.values;
    if (!sampler_used[s]) {  // drives nothing: kept as it is, not evaluated
      parsed.width = 1;
      parsed.values.clear();
      continue;
    }
    KOMA_ASSIGN_OR_RETURN(AccessorData output,
                          ReadAccessor(model, sampler.output, path + ".output", keys_left));
    const bool cubic = parsed.interpolation == GltfInterpolation::kCubicSpline;
    const size_t per_key = (cubic ? 3 : 1) * parsed.times.size();
    int width = sampler_width[s];
    if (width == 0) {  // weights: the morph-target count, from the counts
      if (output.components != 1 || output.values.empty() || output.values.size() % per_key != 0) {
        return Invalid(path + ".output",
                       absl::StrCat(output.values.size(), " weights for ", parsed.times.size(),
                                    " keys: expected a SCALAR accessor with a whole number of "
                                    "morph-target weights per key",
                                    cubic ? " (x3 for CUBICSPLINE)" : ""));
      }
      width = static_cast<int>(output.values.size() / per_key);
    } else if (output.components != width) {
      return Invalid(path + ".output",
                     absl::StrCat(output.components, " components per element, expected ", width,
                                  width == 4 ? " (VEC4 rotation)" : " (VEC3)"));
    } else if (output.values.size() != per_key * static_cast<size_t>(width)) {
      return Invalid(
          path + ".output",
          absl::StrCat(output.values.size() / static_cast<size_t>(width), " elements for ",
                       parsed.times.size(), " keys, expected ", per_key,
                       cubic ? " (in-tangent, value, out-tangent per key)" : ""));
    }
    if (cubic && parsed.times.size() < 2) {
      return Invalid(path, "CUBICSPLINE needs at least 2 keys");
    }
    if (output.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && !output.normalized) {
      return Invalid(path + ".output", "integer values must be normalized");
    }
    for (size_t k = 0; k < output.values.size(); ++k) {
      if (!std::isfinite(output.values[k])) {
        return Invalid(path + ".output", absl::StrCat("value ", k, " is not finite"));
      }
    }
    parsed.width = width;
    parsed.values = std::move(output.values);
  }
  return absl::OkStatus();
}

}  // namespace

bool IsGlb(std::string_view bytes) { return bytes.size() >= 4 && bytes.substr(0, 4) == "glTF"; }

absl::StatusOr<GltfDocument> ReadGltf(std::string_view bytes, const GltfReadLimits& limits) {
  GltfDocument document;
  document.binary = IsGlb(bytes);
  std::string_view json_text = bytes;
  if (document.binary) {
    KOMA_ASSIGN_OR_RETURN(const GlbChunks chunks, SplitGlb(bytes));
    json_text = chunks.json;
  }
  KOMA_ASSIGN_OR_RETURN(document.json, ParseJson(json_text));
  KOMA_RETURN_IF_ERROR(CheckGltfJson(document.json, limits));
  KOMA_RETURN_IF_ERROR(CheckSelfContained(document.json, document.binary));
  KOMA_RETURN_IF_ERROR(StopReason());  // each phase below reads the whole file
  KOMA_ASSIGN_OR_RETURN(const tinygltf::Model model, LoadModel(bytes, document.binary));
  KOMA_RETURN_IF_ERROR(StopReason());
  KOMA_RETURN_IF_ERROR(CheckCounts(document.json, model));
  document.buffers.reserve(model.buffers.size());
  for (const tinygltf::Buffer& buffer : model.buffers) {
    document.buffers.emplace_back(buffer.data.begin(), buffer.data.end());
  }
  KOMA_RETURN_IF_ERROR(BuildHierarchy(model, document));
  KOMA_RETURN_IF_ERROR(FindJoints(model, document));
  int64_t keys_left = limits.max_keys;
  document.animations.resize(model.animations.size());
  StopPoll stop(/*steps_between_checks=*/64);  // animations
  for (size_t a = 0; a < model.animations.size(); ++a) {
    if (stop.Stop()) return stop.status();
    KOMA_RETURN_IF_ERROR(ReadAnimation(model, a, keys_left, document.animations[a]));
  }
  return document;
}

}  // namespace koma::formats

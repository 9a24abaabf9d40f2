// WriteGltf: the file's own JSON and buffers with the retimed animations' samplers replaced,
// what only the old samplers used removed, everything else as it was.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/gltf.h"
#include "formats/gltf_internal.h"

namespace koma::formats {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kFloat = 5126;  // TINYGLTF_COMPONENT_TYPE_FLOAT

// Index fields a visitor may read or rewrite. Visits every place glTF 2.0 and the extensions
// koma knows put an accessor index (kAccessor) or a buffer view index (kView).
enum class Ref { kAccessor, kView };

bool IsIndex(const Json& value) { return value.is_number_integer() && value.get<int64_t>() >= 0; }

template <typename Visit>
void VisitIndex(Json& holder, const char* key, Ref kind, Visit& visit) {
  if (!holder.is_object()) return;
  const auto it = holder.find(key);
  if (it != holder.end() && IsIndex(*it)) visit(kind, *it);
}

template <typename Visit>
void VisitMapValues(Json& map, Ref kind, Visit& visit) {
  if (!map.is_object()) return;
  for (auto& entry : map.items()) {
    if (IsIndex(entry.value())) visit(kind, entry.value());
  }
}

// Accessor references outside the animations (and, when `animations`, inside those not in
// `skip_animations`).
template <typename Visit>
void VisitAccessorRefs(Json& json, const std::set<int>& skip_animations, Visit& visit) {
  if (auto meshes = json.find("meshes"); meshes != json.end() && meshes->is_array()) {
    for (Json& mesh : *meshes) {
      if (!mesh.is_object()) continue;
      auto primitives = mesh.find("primitives");
      if (primitives == mesh.end() || !primitives->is_array()) continue;
      for (Json& primitive : *primitives) {
        if (!primitive.is_object()) continue;
        if (auto attributes = primitive.find("attributes"); attributes != primitive.end()) {
          VisitMapValues(*attributes, Ref::kAccessor, visit);
        }
        VisitIndex(primitive, "indices", Ref::kAccessor, visit);
        if (auto targets = primitive.find("targets");
            targets != primitive.end() && targets->is_array()) {
          for (Json& target : *targets) VisitMapValues(target, Ref::kAccessor, visit);
        }
      }
    }
  }
  if (auto skins = json.find("skins"); skins != json.end() && skins->is_array()) {
    for (Json& skin : *skins) VisitIndex(skin, "inverseBindMatrices", Ref::kAccessor, visit);
  }
  if (auto nodes = json.find("nodes"); nodes != json.end() && nodes->is_array()) {
    for (Json& node : *nodes) {
      if (!node.is_object()) continue;
      auto extensions = node.find("extensions");
      if (extensions == node.end() || !extensions->is_object()) continue;
      auto instancing = extensions->find("EXT_mesh_gpu_instancing");
      if (instancing == extensions->end() || !instancing->is_object()) continue;
      if (auto attributes = instancing->find("attributes"); attributes != instancing->end()) {
        VisitMapValues(*attributes, Ref::kAccessor, visit);
      }
    }
  }
  if (auto animations = json.find("animations");
      animations != json.end() && animations->is_array()) {
    for (size_t a = 0; a < animations->size(); ++a) {
      if (skip_animations.count(static_cast<int>(a)) > 0) continue;
      Json& animation = (*animations)[a];
      if (!animation.is_object()) continue;
      auto samplers = animation.find("samplers");
      if (samplers == animation.end() || !samplers->is_array()) continue;
      for (Json& sampler : *samplers) {
        VisitIndex(sampler, "input", Ref::kAccessor, visit);
        VisitIndex(sampler, "output", Ref::kAccessor, visit);
      }
    }
  }
}

// Buffer view references outside the accessors: images, KHR_draco_mesh_compression.
template <typename Visit>
void VisitOtherViewRefs(Json& json, Visit& visit) {
  if (auto images = json.find("images"); images != json.end() && images->is_array()) {
    for (Json& image : *images) VisitIndex(image, "bufferView", Ref::kView, visit);
  }
  if (auto meshes = json.find("meshes"); meshes != json.end() && meshes->is_array()) {
    for (Json& mesh : *meshes) {
      if (!mesh.is_object()) continue;
      auto primitives = mesh.find("primitives");
      if (primitives == mesh.end() || !primitives->is_array()) continue;
      for (Json& primitive : *primitives) {
        if (!primitive.is_object()) continue;
        auto extensions = primitive.find("extensions");
        if (extensions == primitive.end() || !extensions->is_object()) continue;
        auto draco = extensions->find("KHR_draco_mesh_compression");
        if (draco != extensions->end()) VisitIndex(*draco, "bufferView", Ref::kView, visit);
      }
    }
  }
}

// An accessor's buffer view references (its own and its sparse parts').
template <typename Visit>
void VisitAccessorViews(Json& accessor, Visit& visit) {
  VisitIndex(accessor, "bufferView", Ref::kView, visit);
  if (!accessor.is_object()) return;
  auto sparse = accessor.find("sparse");
  if (sparse == accessor.end() || !sparse->is_object()) return;
  for (const char* part : {"indices", "values"}) {
    if (auto it = sparse->find(part); it != sparse->end()) {
      VisitIndex(*it, "bufferView", Ref::kView, visit);
    }
  }
}

// t as a 32-bit float no later than t.
float FloatAtOrBefore(double t) {
  float f = static_cast<float>(t);
  if (static_cast<double>(f) > t) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

Json& ArrayMember(Json& json, const char* key) {
  Json& member = json[key];
  if (!member.is_array()) member = Json::array();
  return member;
}

// Drops the byte ranges of removed views from buffer `b`, moving the kept views down. A
// kept range keeps its offset modulo 8, so every accessor stays aligned.
// A view's byteOffset or byteLength in bytes (0 when absent); nullopt when it is not a whole,
// non-negative number (a fuzzed 1.7e87 would not convert to size_t).
std::optional<size_t> ViewBytes(const Json& view, const char* key) {
  const auto it = view.find(key);
  if (it == view.end()) return size_t{0};
  if (!it->is_number_unsigned()) return std::nullopt;
  return it->get<size_t>();
}

// The buffer index of a view; -1 when it has none or it is not a whole number.
int64_t ViewBuffer(const Json& view) {
  const auto it = view.find("buffer");
  return it != view.end() && it->is_number_integer() ? it->get<int64_t>() : -1;
}

void CompactBuffer(int b, const std::vector<bool>& removed_view, Json& views, std::string& buffer) {
  struct Range {
    size_t begin, end;
  };
  std::vector<Range> ranges;
  for (size_t v = 0; v < views.size(); ++v) {
    const Json& view = views[v];
    if (removed_view[v] || !view.is_object() || ViewBuffer(view) != b) continue;
    const std::optional<size_t> offset = ViewBytes(view, "byteOffset");
    const std::optional<size_t> length = ViewBytes(view, "byteLength");
    // A view this writer cannot place: leave the buffer as it was (unused bytes stay).
    if (!offset || !length || *offset > buffer.size()) return;
    ranges.push_back(
        {*offset, *length > buffer.size() - *offset ? buffer.size() : *offset + *length});
  }
  if (ranges.empty()) return;  // nothing left to keep: the buffer stays as it was
  std::sort(ranges.begin(), ranges.end(),
            [](const Range& x, const Range& y) { return x.begin < y.begin; });
  std::vector<Range> merged;
  for (const Range& r : ranges) {
    if (!merged.empty() && r.begin <= merged.back().end) {
      merged.back().end = std::max(merged.back().end, r.end);
    } else {
      merged.push_back(r);
    }
  }
  std::string out;
  std::vector<size_t> new_begin;
  for (const Range& r : merged) {
    while (out.size() % 8 != r.begin % 8) out.push_back('\0');
    new_begin.push_back(out.size());
    out.append(buffer, r.begin, r.end - r.begin);
  }
  for (size_t v = 0; v < views.size(); ++v) {
    Json& view = views[v];
    if (removed_view[v] || !view.is_object() || ViewBuffer(view) != b) continue;
    const size_t offset = *ViewBytes(view, "byteOffset");  // checked above
    size_t m = 0;
    while (m + 1 < merged.size() && merged[m + 1].begin <= offset) ++m;
    const size_t moved = new_begin[m] + (offset - merged[m].begin);
    if (moved != offset || view.contains("byteOffset")) view["byteOffset"] = moved;
  }
  buffer = std::move(out);
}

}  // namespace

absl::StatusOr<std::string> WriteGltf(const GltfDocument& document,
                                      const std::vector<GltfAnimationKeys>& keys,
                                      bool keep_original) {
  Json json = document.json;
  // Members created here are dropped again if they stay empty; the file's own stay as they were.
  const bool had_animations = json.contains("animations");
  const bool had_accessors = json.contains("accessors");
  const bool had_views = json.contains("bufferViews");
  std::vector<std::string> buffers = document.buffers;
  std::vector<bool> buffer_changed(buffers.size(), false);
  std::set<int> replaced;
  for (const GltfAnimationKeys& k : keys) replaced.insert(k.animation);

  // Every top-level member this function adds to is made before any reference into `json` is
  // taken: ordered_json keeps an object's members in one vector, so adding or erasing a member
  // moves the others and would leave such references dangling.
  const bool adds_buffer = !keys.empty() && buffers.empty();
  for (const char* key : {"accessors", "bufferViews", "animations"}) ArrayMember(json, key);
  if (adds_buffer) ArrayMember(json, "buffers");

  // 1. Accessors only the replaced samplers use, and buffer views only those accessors use.
  Json& accessors = ArrayMember(json, "accessors");
  Json& views = ArrayMember(json, "bufferViews");
  std::vector<bool> removed_accessor(accessors.size(), false);
  std::vector<bool> removed_view(views.size(), false);
  if (!keep_original && !replaced.empty()) {
    std::vector<bool> used_elsewhere(accessors.size(), false);
    auto mark_elsewhere = [&](Ref, Json& index) {
      const auto i = index.get<size_t>();
      if (i < used_elsewhere.size()) used_elsewhere[i] = true;
    };
    VisitAccessorRefs(json, replaced, mark_elsewhere);
    for (int a : replaced) {
      Json& animation = json["animations"][static_cast<size_t>(a)];
      auto samplers = animation.find("samplers");
      if (samplers == animation.end() || !samplers->is_array()) continue;
      for (Json& sampler : *samplers) {
        for (const char* key : {"input", "output"}) {
          auto it = sampler.find(key);
          if (it == sampler.end() || !IsIndex(*it)) continue;
          const auto i = it->get<size_t>();
          if (i < removed_accessor.size() && !used_elsewhere[i]) removed_accessor[i] = true;
        }
      }
    }
    std::vector<bool> view_kept_use(views.size(), false);
    std::vector<bool> view_removed_use(views.size(), false);
    for (size_t i = 0; i < accessors.size(); ++i) {
      auto mark = [&](Ref, Json& index) {
        const auto v = index.get<size_t>();
        if (v >= views.size()) return;
        (removed_accessor[i] ? view_removed_use : view_kept_use)[v] = true;
      };
      VisitAccessorViews(accessors[i], mark);
    }
    auto mark_other = [&](Ref, Json& index) {
      const auto v = index.get<size_t>();
      if (v < views.size()) view_kept_use[v] = true;
    };
    VisitOtherViewRefs(json, mark_other);
    for (size_t v = 0; v < views.size(); ++v) {
      removed_view[v] = view_removed_use[v] && !view_kept_use[v];
    }
  }

  // 2. Drop their bytes, then the entries, renumbering every reference.
  std::vector<bool> buffer_loses_view(buffers.size(), false);
  for (size_t v = 0; v < views.size(); ++v) {
    if (!removed_view[v]) continue;
    const int64_t b = views[v].is_object() ? ViewBuffer(views[v]) : -1;
    if (b >= 0 && static_cast<uint64_t>(b) < buffers.size()) {
      buffer_loses_view[static_cast<size_t>(b)] = true;
    }
  }
  for (size_t b = 0; b < buffers.size(); ++b) {
    if (!buffer_loses_view[b]) continue;
    CompactBuffer(static_cast<int>(b), removed_view, views, buffers[b]);
    buffer_changed[b] = true;
  }
  std::vector<int64_t> accessor_map(accessors.size(), -1);
  std::vector<int64_t> view_map(views.size(), -1);
  {
    Json kept = Json::array();
    for (size_t i = 0; i < accessors.size(); ++i) {
      if (removed_accessor[i]) continue;
      accessor_map[i] = static_cast<int64_t>(kept.size());
      kept.push_back(std::move(accessors[i]));
    }
    accessors = std::move(kept);
    kept = Json::array();
    for (size_t v = 0; v < views.size(); ++v) {
      if (removed_view[v]) continue;
      view_map[v] = static_cast<int64_t>(kept.size());
      kept.push_back(std::move(views[v]));
    }
    views = std::move(kept);
  }
  auto renumber = [&](Ref kind, Json& index) {
    const auto i = index.get<size_t>();
    const std::vector<int64_t>& map = kind == Ref::kAccessor ? accessor_map : view_map;
    if (i < map.size() && map[i] >= 0) index = map[i];
  };
  VisitAccessorRefs(json, {}, renumber);
  VisitOtherViewRefs(json, renumber);
  for (Json& accessor : accessors) VisitAccessorViews(accessor, renumber);

  KOMA_RETURN_IF_ERROR(StopReason());  // steps 1 and 2 walk the whole document
  // 3. The new keys: one time accessor per animation, one output accessor per channel, each
  // in its own buffer view at the end of buffer 0.
  if (adds_buffer) {
    buffers.emplace_back();
    buffer_changed.push_back(true);
    Json& list = ArrayMember(json, "buffers");
    list.push_back(Json::object({{"byteLength", 0}}));
  }
  auto add_floats = [&](const std::vector<float>& values, const char* type, size_t count,
                        bool min_max) -> int64_t {
    std::string& buffer = buffers[0];
    buffer_changed[0] = true;
    while (buffer.size() % 4 != 0) buffer.push_back('\0');
    Json view = Json::object();
    view["buffer"] = 0;
    view["byteOffset"] = buffer.size();
    view["byteLength"] = values.size() * sizeof(float);
    buffer.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    views.push_back(std::move(view));
    Json accessor = Json::object();
    accessor["bufferView"] = views.size() - 1;
    accessor["componentType"] = kFloat;
    accessor["count"] = count;
    accessor["type"] = type;
    if (min_max && !values.empty()) {
      accessor["min"] = Json::array({values.front()});
      accessor["max"] = Json::array({values.back()});
    }
    accessors.push_back(std::move(accessor));
    return static_cast<int64_t>(accessors.size()) - 1;
  };
  Json& animations = ArrayMember(json, "animations");
  std::vector<Json> appended;
  StopPoll stop(/*steps_between_checks=*/4096);  // keys written
  for (const GltfAnimationKeys& k : keys) {
    if (stop.Stop(static_cast<int64_t>(k.times.size() * (k.values.size() + 1)))) {
      return stop.status();
    }
    if (k.animation < 0 || static_cast<size_t>(k.animation) >= animations.size() ||
        static_cast<size_t>(k.animation) >= document.animations.size()) {
      return absl::InternalError(absl::StrCat("glTF writer: no animation ", k.animation));
    }
    const GltfAnimation& source = document.animations[static_cast<size_t>(k.animation)];
    if (k.values.size() != source.clip.channels.size()) {
      return absl::InternalError("glTF writer: one value list per channel expected");
    }
    std::vector<float> times(k.times.size());
    for (size_t i = 0; i < k.times.size(); ++i) times[i] = FloatAtOrBefore(k.times[i]);
    const int64_t input = add_floats(times, "SCALAR", times.size(), /*min_max=*/true);
    Json& original = animations[static_cast<size_t>(k.animation)];
    const Json& original_channels = original["channels"];
    Json samplers = Json::array();
    Json channels = Json::array();
    for (size_t c = 0; c < k.values.size(); ++c) {
      const GltfChannel& channel = source.clip.channels[c];
      const int width = source.clip.samplers[static_cast<size_t>(channel.sampler)].width;
      const char* type = channel.path == GltfPath::kRotation  ? "VEC4"
                         : channel.path == GltfPath::kWeights ? "SCALAR"
                                                              : "VEC3";
      if (k.values[c].size() != k.times.size() * static_cast<size_t>(width)) {
        return absl::InternalError("glTF writer: a channel's value count does not match");
      }
      std::vector<float> values(k.values[c].begin(), k.values[c].end());
      const size_t count = channel.path == GltfPath::kWeights ? values.size() : k.times.size();
      const int64_t output = add_floats(values, type, count, /*min_max=*/false);
      samplers.push_back(Json::object(
          {{"input", input}, {"interpolation", k.linear ? "LINEAR" : "STEP"}, {"output", output}}));
      Json out_channel = original_channels[c];
      out_channel["sampler"] = c;
      channels.push_back(std::move(out_channel));
    }
    if (keep_original) {
      const std::string name = source.name.empty()
                                   ? absl::StrCat("animation", k.animation, ".anime")
                                   : absl::StrCat(source.name, ".anime");
      appended.push_back(Json::object(
          {{"channels", std::move(channels)}, {"samplers", std::move(samplers)}, {"name", name}}));
    } else {
      original["channels"] = std::move(channels);
      original["samplers"] = std::move(samplers);
    }
  }
  for (Json& animation : appended) animations.push_back(std::move(animation));
  // Decided before erasing anything: an erase moves the members after it (see above).
  const bool drop_animations = animations.empty() && !had_animations;
  const bool drop_accessors = accessors.empty() && !had_accessors;
  const bool drop_views = views.empty() && !had_views;
  if (drop_animations) json.erase("animations");
  if (drop_accessors) json.erase("accessors");
  if (drop_views) json.erase("bufferViews");

  // 4. Buffers: lengths, and data: URIs (or the GLB's BIN chunk) for the changed ones.
  std::string bin;
  bool has_bin = false;
  if (!buffers.empty()) {
    Json& list = json["buffers"];
    for (size_t b = 0; b < buffers.size(); ++b) {
      Json& entry = list[b];
      const bool is_bin = document.binary && b == 0 && !entry.contains("uri");
      if (is_bin) {
        bin = buffers[0];
        has_bin = true;
      }
      if (!buffer_changed[b]) continue;
      entry["byteLength"] = buffers[b].size();
      if (!is_bin) {
        entry["uri"] = "data:application/octet-stream;base64," + Base64(buffers[b]);
      }
    }
  }
  std::string text;
  try {
    text = document.binary ? json.dump() : json.dump(2) + "\n";
  } catch (const Json::exception& error) {
    return absl::InvalidArgumentError(absl::StrCat("glTF JSON cannot be written: ", error.what()));
  }
  if (!document.binary) return text;
  if (has_bin && bin.size() > 0xFFFFFF00u) {
    return absl::ResourceExhaustedError("glTF: the BIN chunk would pass GLB's 4 GiB limit");
  }
  return JoinGlb(text, has_bin ? std::string_view(bin) : std::string_view());
}

}  // namespace koma::formats

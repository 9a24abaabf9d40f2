#include "formats/fbx_scene.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/status_macros.h"

namespace koma::formats {
namespace {

// KeyAttrFlags bits (FbxAnimCurveDef).
constexpr uint32_t kInterpolationConstant = 0x00000002;
constexpr uint32_t kInterpolationLinear = 0x00000004;
constexpr uint32_t kInterpolationCubic = 0x00000008;
constexpr uint32_t kConstantNext = 0x00000100;
constexpr uint32_t kWeightedRight = 0x01000000;
constexpr uint32_t kWeightedNextLeft = 0x02000000;
constexpr double kDefaultWeight = 1.0 / 3.0;

absl::Status Invalid(const std::string& where, absl::string_view what) {
  return absl::InvalidArgumentError(absl::StrCat(where, ": ", what));
}

const FbxNode* TopLevel(const FbxDocument& document, std::string_view name) {
  for (const FbxNode& node : document.nodes) {
    if (node.name == name) return &node;
  }
  return nullptr;
}

// A Properties70 block: name -> the P record's values (after name, type, label, flags).
using Properties = std::map<std::string, std::vector<const FbxProperty*>>;

void AddProperties(const FbxNode* owner, Properties& out) {
  const FbxNode* block = owner == nullptr ? nullptr : owner->Child("Properties70");
  if (block == nullptr) return;
  for (const FbxNode& p : block->children) {
    if (p.properties.size() < 4 || p.properties[0].type != 'S') continue;
    std::vector<const FbxProperty*> values;
    for (size_t i = 4; i < p.properties.size(); ++i) values.push_back(&p.properties[i]);
    out[p.properties[0].bytes] = std::move(values);
  }
}

double Number(const FbxProperty& p) {
  return p.type == 'F' || p.type == 'D' ? p.real : static_cast<double>(p.integer);
}

std::optional<double> Scalar(const Properties& properties, const std::string& name) {
  const auto it = properties.find(name);
  if (it == properties.end() || it->second.empty()) return std::nullopt;
  return Number(*it->second[0]);
}

std::array<double, 3> Vector(const Properties& properties, const std::string& name,
                             std::array<double, 3> fallback) {
  const auto it = properties.find(name);
  if (it == properties.end() || it->second.size() < 3) return fallback;
  return {Number(*it->second[0]), Number(*it->second[1]), Number(*it->second[2])};
}

// "Name\0\1Class" -> "Name".
std::string ObjectName(const FbxNode& object) {
  if (object.properties.size() < 2) return "";
  const std::string& full = object.properties[1].bytes;
  const size_t separator = full.find(std::string("\0\1", 2));
  return separator == std::string::npos ? full : full.substr(0, separator);
}

int64_t ObjectId(const FbxNode& object) {
  return object.properties.empty() ? 0 : object.properties[0].integer;
}

std::string Where(const FbxNode& object) {
  return absl::StrCat("Objects/", object.name, " ", ObjectId(object), " \"", ObjectName(object),
                      "\"");
}

// Key times already inflated, by their compressed bytes: a baked take's curves all have the
// same times (Blender's exporter, the vendors'), inflated once instead of once per curve.
using KeyTimeCache = std::unordered_map<std::string_view, std::vector<int64_t>>;

absl::StatusOr<std::vector<int64_t>> KeyTimes(const FbxProperty& times, KeyTimeCache& cache) {
  if (times.encoding != 1 || times.type != 'l') return FbxIntegers(times);
  const auto found = cache.find(times.encoded);
  if (found != cache.end() && found->second.size() == times.count) return found->second;
  KOMA_ASSIGN_OR_RETURN(std::vector<int64_t> decoded, FbxIntegers(times));
  cache[times.encoded] = decoded;
  return decoded;
}

absl::StatusOr<FbxKeyCurve> ReadCurve(const FbxNode& object, KeyTimeCache& time_cache) {
  const std::string where = Where(object);
  const auto array = [&](const char* name) -> const FbxProperty* {
    const FbxNode* node = object.Child(name);
    return node == nullptr || node->properties.empty() ? nullptr : &node->properties[0];
  };
  FbxKeyCurve curve;
  const FbxProperty* times = array("KeyTime");
  const FbxProperty* values = array("KeyValueFloat");
  if (times == nullptr || values == nullptr) {
    return Invalid(where, "an AnimationCurve without KeyTime and KeyValueFloat");
  }
  const auto in_field = [&](absl::Status status, const char* field) {
    return absl::Status(status.code(), absl::StrCat(where, " ", field, ": ", status.message()));
  };
  absl::StatusOr<std::vector<int64_t>> t = KeyTimes(*times, time_cache);
  if (!t.ok()) return in_field(t.status(), "KeyTime");
  absl::StatusOr<std::vector<double>> v = FbxReals(*values);
  if (!v.ok()) return in_field(v.status(), "KeyValueFloat");
  if (t->size() != v->size()) {
    return Invalid(where, absl::StrCat("KeyValueFloat has ", v->size(), " values for ", t->size(),
                                       " KeyTime keys"));
  }
  for (size_t k = 1; k < t->size(); ++k) {
    if ((*t)[k] <= (*t)[k - 1]) {
      return Invalid(where, absl::StrCat("KeyTime: key ", k, " is not after key ", k - 1));
    }
  }
  curve.times = *std::move(t);
  curve.values = *std::move(v);
  const size_t keys = curve.times.size();
  curve.segments.assign(keys, FbxKeyCurve::Segment::kLinear);
  const FbxProperty* flags = array("KeyAttrFlags");
  const FbxProperty* data = array("KeyAttrDataFloat");
  const FbxProperty* counts = array("KeyAttrRefCount");
  if (flags == nullptr || counts == nullptr) return curve;  // linear, as the SDK's default
  absl::StatusOr<std::vector<int64_t>> f = FbxIntegers(*flags);
  if (!f.ok()) return in_field(f.status(), "KeyAttrFlags");
  absl::StatusOr<std::vector<int64_t>> c = FbxIntegers(*counts);
  if (!c.ok()) return in_field(c.status(), "KeyAttrRefCount");
  std::vector<double> d;
  if (data != nullptr) {
    absl::StatusOr<std::vector<double>> read = FbxReals(*data);
    if (!read.ok()) return in_field(read.status(), "KeyAttrDataFloat");
    d = *std::move(read);
  }
  if (f->size() != c->size() || d.size() < 4 * f->size()) {
    return Invalid(where,
                   absl::StrCat(f->size(), " KeyAttrFlags, ", c->size(), " KeyAttrRefCount and ",
                                d.size(), " KeyAttrDataFloat (4 per attribute) do not match"));
  }
  size_t key = 0;
  for (size_t a = 0; a < f->size(); ++a) {
    const auto bits = static_cast<uint32_t>((*f)[a]);
    // Two 16-bit weights (x 10,000) in the bits of the third float.
    const float packed = static_cast<float>(d[4 * a + 2]);
    uint32_t weights = 0;
    std::memcpy(&weights, &packed, 4);
    FbxKeyCurve::Segment segment = FbxKeyCurve::Segment::kLinear;
    if (bits & kInterpolationConstant) {
      segment = bits & kConstantNext ? FbxKeyCurve::Segment::kConstantNext
                                     : FbxKeyCurve::Segment::kConstant;
    } else if (bits & kInterpolationCubic) {
      segment = FbxKeyCurve::Segment::kCubic;
    } else if (!(bits & kInterpolationLinear)) {
      return Invalid(where, absl::StrCat("KeyAttrFlags[", a, "]: 0x", absl::Hex(bits),
                                         " has no interpolation (constant, linear or cubic)"));
    }
    for (int64_t n = 0; n < (*c)[a]; ++n, ++key) {
      if (key >= keys) {
        return Invalid(where, absl::StrCat("KeyAttrRefCount covers more than the ", keys, " keys"));
      }
      curve.segments[key] = segment;
      if (segment != FbxKeyCurve::Segment::kCubic) continue;
      if (curve.right_slopes.empty()) {  // the first cubic key: a baked take often has none
        curve.right_slopes.assign(keys, 0.0);
        curve.next_left_slopes.assign(keys, 0.0);
        curve.right_weights.assign(keys, kDefaultWeight);
        curve.next_left_weights.assign(keys, kDefaultWeight);
      }
      curve.right_slopes[key] = d[4 * a];
      curve.next_left_slopes[key] = d[4 * a + 1];
      if (bits & kWeightedRight) curve.right_weights[key] = (weights & 0xffff) / 10000.0;
      if (bits & kWeightedNextLeft) curve.next_left_weights[key] = (weights >> 16) / 10000.0;
    }
  }
  if (key != keys) {
    return Invalid(where, absl::StrCat("KeyAttrRefCount covers ", key, " of the ", keys, " keys"));
  }
  return curve;
}

struct Connection {
  int64_t child, parent;
  std::string property;  // OP: the parent's property ("Lcl Translation", "d|X")
};

}  // namespace

double FbxTimeModeFps(int64_t time_mode, double custom_rate) {
  switch (time_mode) {
    case 0:  // the default mode: the SDK's 30 frames a second
    case 6:
    case 7:
      return 30.0;
    case 1:
      return 120.0;
    case 2:
      return 100.0;
    case 3:
      return 60.0;
    case 4:
      return 50.0;
    case 5:
      return 48.0;
    case 8:
    case 9:
      return 30.0 / 1.001;
    case 10:
      return 25.0;
    case 11:
      return 24.0;
    case 12:
      return 1000.0;
    case 13:
      return 24.0 / 1.001;
    case 14:
      return custom_rate > 0 ? custom_rate : 0.0;
    case 15:
      return 96.0;
    case 16:
      return 72.0;
    case 17:
      return 60.0 / 1.001;
    case 18:
      return 120.0 / 1.001;
    default:
      return 0.0;
  }
}

absl::StatusOr<FbxTakeRig> ReadFbxTakeRig(const FbxDocument& document, const std::string& take) {
  FbxTakeRig out;
  Properties global;
  AddProperties(TopLevel(document, "GlobalSettings"), global);
  out.fps = FbxTimeModeFps(static_cast<int64_t>(Scalar(global, "TimeMode").value_or(0)),
                           Scalar(global, "CustomFrameRate").value_or(0));
  if (!(out.fps > 0)) {
    return Invalid(
        "GlobalSettings",
        absl::StrCat("TimeMode ", Scalar(global, "TimeMode").value_or(0), " with CustomFrameRate ",
                     Scalar(global, "CustomFrameRate").value_or(0), " gives no frame rate"));
  }
  // The Model template's defaults (Definitions/ObjectType "Model"/PropertyTemplate).
  Properties model_template;
  if (const FbxNode* definitions = TopLevel(document, "Definitions")) {
    for (const FbxNode& type : definitions->children) {
      if (type.name != "ObjectType" || type.properties.empty() ||
          type.properties[0].bytes != "Model") {
        continue;
      }
      AddProperties(type.Child("PropertyTemplate"), model_template);
    }
  }
  const FbxNode* objects = TopLevel(document, "Objects");
  const FbxNode* connections = TopLevel(document, "Connections");
  if (objects == nullptr || connections == nullptr) {
    return absl::InvalidArgumentError("the file has no Objects or no Connections: no scene");
  }
  std::map<int64_t, const FbxNode*> by_id;
  for (const FbxNode& object : objects->children) by_id[ObjectId(object)] = &object;
  std::vector<Connection> links;
  for (const FbxNode& c : connections->children) {
    if (c.name != "C" || c.properties.size() < 3) continue;
    links.push_back({c.properties[1].integer, c.properties[2].integer,
                     c.properties.size() > 3 ? c.properties[3].bytes : ""});
  }
  const auto is = [&](int64_t id, std::string_view name) {
    const auto it = by_id.find(id);
    return it != by_id.end() && it->second->name == name;
  };

  // Takes: the stacks, their layers (in connection order).
  std::vector<const FbxNode*> stacks;
  for (const FbxNode& object : objects->children) {
    if (object.name == "AnimationStack") stacks.push_back(&object);
  }
  if (stacks.empty()) return absl::InvalidArgumentError("the file has no take (AnimationStack)");
  std::string wanted = take;
  if (wanted.empty()) {
    const FbxNode* takes = TopLevel(document, "Takes");
    const FbxNode* current = takes == nullptr ? nullptr : takes->Child("Current");
    if (current != nullptr && !current->properties.empty()) wanted = current->properties[0].bytes;
  }
  const FbxNode* stack = nullptr;
  std::vector<std::string> names;
  for (const FbxNode* s : stacks) {
    Properties p;
    AddProperties(s, p);
    FbxTakeInfo info;
    info.name = ObjectName(*s);
    info.start = static_cast<int64_t>(Scalar(p, "LocalStart").value_or(0));
    info.stop = static_cast<int64_t>(Scalar(p, "LocalStop").value_or(0));
    for (const Connection& link : links) {
      info.layers += link.parent == ObjectId(*s) && is(link.child, "AnimationLayer");
    }
    out.takes.push_back(info);
    names.push_back(absl::StrCat("\"", info.name, "\""));
    if (info.name == wanted) {
      stack = s;
      out.take = info;
    }
  }
  if (stack == nullptr && take.empty()) {  // Takes/Current names no stack: the first
    stack = stacks.front();
    out.take = out.takes.front();
  }
  if (stack == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat("take \"", take, "\": not in the file (it has ",
                                                   absl::StrJoin(names, ", "), ")"));
  }
  // The base layer: the stack's first.
  int64_t layer = 0;
  for (const Connection& link : links) {
    if (link.parent == ObjectId(*stack) && is(link.child, "AnimationLayer")) {
      layer = link.child;
      break;
    }
  }

  // Models and their parents.
  std::map<int64_t, int64_t> parent_of;
  for (const Connection& link : links) {
    if (is(link.child, "Model") && is(link.parent, "Model") && link.property.empty()) {
      parent_of[link.child] = link.parent;
    }
  }
  // The curve nodes of the layer, bound to a model's property; their curves per axis.
  std::set<int64_t> in_layer;
  for (const Connection& link : links) {
    if (link.parent == layer && is(link.child, "AnimationCurveNode")) in_layer.insert(link.child);
  }
  struct Binding {
    int64_t model;
    int kind;  // 0 T, 1 R, 2 S
    std::array<int64_t, 3> curves{0, 0, 0};
  };
  std::map<int64_t, Binding> bindings;  // by curve node id
  for (const Connection& link : links) {
    if (in_layer.count(link.child) == 0 || !is(link.parent, "Model")) continue;
    const int kind = link.property == "Lcl Translation" ? 0
                     : link.property == "Lcl Rotation"  ? 1
                     : link.property == "Lcl Scaling"   ? 2
                                                        : -1;
    if (kind >= 0) bindings[link.child] = {link.parent, kind};
  }
  for (const Connection& link : links) {
    const auto b = bindings.find(link.parent);
    if (b == bindings.end() || !is(link.child, "AnimationCurve")) continue;
    const int axis = link.property == "d|X"   ? 0
                     : link.property == "d|Y" ? 1
                     : link.property == "d|Z" ? 2
                                              : -1;
    if (axis >= 0) b->second.curves[static_cast<size_t>(axis)] = link.child;
  }

  // The models kept: bones and moving ones, with their ancestors; parents first.
  std::set<int64_t> kept;
  for (const auto& [id, object] : by_id) {
    if (object->name != "Model" || object->properties.size() < 3) continue;
    const std::string& type = object->properties[2].bytes;
    if (type == "LimbNode" || type == "Root" || type == "Null") kept.insert(id);
  }
  for (const auto& [node, binding] : bindings) kept.insert(binding.model);
  // Their ancestors, each walked once (a walk stops at a model walked before), so a long
  // chain costs its length, not its length squared.
  std::set<int64_t> walked;
  for (int64_t id : std::vector<int64_t>(kept.begin(), kept.end())) {
    std::set<int64_t> this_walk;
    for (int64_t at = id; walked.insert(at).second;) {
      this_walk.insert(at);
      const auto p = parent_of.find(at);
      if (p == parent_of.end()) break;
      if (this_walk.count(p->second)) return Invalid(Where(*by_id[id]), "its parents form a cycle");
      kept.insert(p->second);
      at = p->second;
    }
  }
  std::map<int64_t, int> index_of;
  // File order, each after its parent (no recursion: a chain of models may be long).
  std::vector<int64_t> order;
  std::set<int64_t> placed;
  for (const FbxNode& object : objects->children) {
    if (object.name != "Model" || !kept.count(ObjectId(object))) continue;
    std::vector<int64_t> chain;  // the model and its ancestors not placed yet, child first
    for (int64_t at = ObjectId(object); !placed.count(at);) {
      chain.push_back(at);
      placed.insert(at);
      const auto p = parent_of.find(at);
      if (p == parent_of.end()) break;
      at = p->second;
    }
    order.insert(order.end(), chain.rbegin(), chain.rend());
  }
  // Each model's bindings, for the loop below.
  std::map<int64_t, std::vector<const Binding*>> bindings_of;
  for (const auto& [node, binding] : bindings) bindings_of[binding.model].push_back(&binding);
  std::map<int64_t, int> curve_index;
  KeyTimeCache time_cache;
  for (int64_t id : order) {
    const FbxNode& object = *by_id[id];
    Properties p = model_template;
    AddProperties(&object, p);
    FbxRigNode node;
    const auto parent = parent_of.find(id);
    node.parent = parent == parent_of.end() || !index_of.count(parent->second)
                      ? -1
                      : index_of[parent->second];
    node.translation = Vector(p, "Lcl Translation", {0, 0, 0});
    node.rotation = Vector(p, "Lcl Rotation", {0, 0, 0});
    node.scaling = Vector(p, "Lcl Scaling", {1, 1, 1});
    node.rotation_offset = Vector(p, "RotationOffset", {0, 0, 0});
    node.rotation_pivot = Vector(p, "RotationPivot", {0, 0, 0});
    node.scaling_offset = Vector(p, "ScalingOffset", {0, 0, 0});
    node.scaling_pivot = Vector(p, "ScalingPivot", {0, 0, 0});
    if (Scalar(p, "RotationActive").value_or(0) != 0) {
      node.pre_rotation = Vector(p, "PreRotation", {0, 0, 0});
      node.post_rotation = Vector(p, "PostRotation", {0, 0, 0});
      const double order_number = Scalar(p, "RotationOrder").value_or(0);
      if (order_number < 0 || order_number > 5) {
        return Invalid(Where(object), absl::StrCat("RotationOrder ", order_number,
                                                   " is not 0-5 (eEulerXYZ..eEulerZYX)"));
      }
      node.order = static_cast<FbxRotationOrder>(static_cast<int>(order_number));
    }
    // The SDK's default (its templates' 0, RrSs) when neither the model nor the template
    // says; every exporter seen writes 1 (RSrs) on each model.
    const double inherit = Scalar(p, "InheritType").value_or(0);
    if (inherit != 0 && inherit != 1 && inherit != 2) {
      return Invalid(Where(object), absl::StrCat("InheritType ", inherit,
                                                 " is not 0-2 (eInheritRrSs..eInheritRrs)"));
    }
    node.inherit = static_cast<FbxInheritType>(static_cast<int>(inherit));
    for (const Binding* binding : bindings_of[id]) {
      std::array<int, 3>& slots = binding->kind == 0   ? node.translation_curves
                                  : binding->kind == 1 ? node.rotation_curves
                                                       : node.scaling_curves;
      for (int a = 0; a < 3; ++a) {
        const int64_t curve_id = binding->curves[static_cast<size_t>(a)];
        if (curve_id == 0) continue;
        auto [at, added] = curve_index.emplace(curve_id, static_cast<int>(out.rig.curves.size()));
        if (added) {
          KOMA_ASSIGN_OR_RETURN(FbxKeyCurve curve, ReadCurve(*by_id[curve_id], time_cache));
          out.rig.curves.push_back(std::move(curve));
          out.curve_ids.push_back(curve_id);
        }
        slots[static_cast<size_t>(a)] = at->second;
      }
    }
    index_of[id] = static_cast<int>(out.rig.nodes.size());
    out.rig.nodes.push_back(node);
    out.names.push_back(ObjectName(object));
    out.types.push_back(object.properties.size() > 2 ? object.properties[2].bytes : "");
    out.ids.push_back(id);
  }
  return out;
}

}  // namespace koma::formats

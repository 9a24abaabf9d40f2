// Small glTF 2.0 files for tests, built in memory: a JSON document plus one binary buffer,
// written as GLB or as .gltf with a data: URI. ArmGltf() is a skinned three-joint arm with a
// two-target morph mesh, VRM-style extensions and extras, and one animation driving rotation,
// translation and morph weights.
#ifndef KOMA_TESTS_TESTING_GLTF_BUILDER_H_
#define KOMA_TESTS_TESTING_GLTF_BUILDER_H_

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "formats/gltf_internal.h"

namespace koma::testing {

struct TestGltf {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  std::string bin;

  // `values` as a FLOAT accessor of `type` in its own buffer view; returns its index.
  int AddFloats(const std::vector<float>& values, const char* type, bool min_max = false) {
    while (bin.size() % 4 != 0) bin.push_back('\0');
    auto& views = json["bufferViews"];
    if (!views.is_array()) views = nlohmann::ordered_json::array();
    views.push_back({{"buffer", 0},
                     {"byteOffset", bin.size()},
                     {"byteLength", values.size() * 4}});
    bin.append(reinterpret_cast<const char*>(values.data()), values.size() * 4);
    const size_t width = std::string(type) == "SCALAR" ? 1
                         : std::string(type) == "VEC4" ? 4
                         : std::string(type) == "VEC2" ? 2
                                                       : 3;
    nlohmann::ordered_json accessor = {{"bufferView", views.size() - 1},
                                       {"componentType", 5126},
                                       {"count", values.size() / width},
                                       {"type", type}};
    if (min_max) {
      accessor["min"] = {*std::min_element(values.begin(), values.end())};
      accessor["max"] = {*std::max_element(values.begin(), values.end())};
    }
    auto& accessors = json["accessors"];
    if (!accessors.is_array()) accessors = nlohmann::ordered_json::array();
    accessors.push_back(accessor);
    return static_cast<int>(accessors.size()) - 1;
  }

  nlohmann::ordered_json WithBuffer(bool glb) const {
    nlohmann::ordered_json out = json;
    nlohmann::ordered_json buffer = {{"byteLength", bin.size()}};
    if (!glb) {
      buffer["uri"] = "data:application/octet-stream;base64," + formats::Base64(bin);
    }
    out["buffers"] = nlohmann::ordered_json::array({buffer});
    return out;
  }
  std::string Glb() const { return formats::JoinGlb(WithBuffer(true).dump(), bin); }
  std::string GltfText() const { return WithBuffer(false).dump(2); }
};

// Per-frame rotation of the arm about z, in degrees, at frame f of 61 (30 fps, 2 s): a
// still start, a fast swing in the middle, a slow settle.
inline double ArmAngle(int f) {
  const double t = f / 60.0;
  return 90 * t * t * (3 - 2 * t);  // smoothstep: slow, fast, slow
}

inline TestGltf ArmGltf(const char* interpolation = "LINEAR") {
  TestGltf g;
  using Json = nlohmann::ordered_json;
  g.json["asset"] = {{"version", "2.0"}, {"generator", "koma tests"}};
  g.json["extensionsUsed"] = {"VRMC_vrm"};
  g.json["extensions"] = {{"VRMC_vrm", {{"specVersion", "1.0"}, {"meta", {{"name", "arm"}}}}}};
  g.json["extras"] = {{"studio", "koma"}, {"take", 3}};
  g.json["scene"] = 0;
  g.json["scenes"] = Json::array({{{"nodes", {0, 3}}}});
  g.json["nodes"] = Json::array(
      {{{"name", "Hips"}, {"translation", {0, 1, 0}}, {"children", {1}}},
       {{"name", "Arm"}, {"translation", {0, 0.5, 0}}, {"children", {2}}},
       {{"name", "Hand"}, {"translation", {0.5, 0, 0}}, {"extras", {{"tip", true}}}},
       {{"name", "Body"}, {"mesh", 0}, {"skin", 0}}});
  // A triangle with two morph targets and per-vertex joints.
  const int positions = g.AddFloats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", true);
  g.json["accessors"][static_cast<size_t>(positions)]["min"] = {0, 0, 0};
  g.json["accessors"][static_cast<size_t>(positions)]["max"] = {1, 1, 0};
  const int target0 = g.AddFloats({0, 0, 0.1f, 0, 0, 0.2f, 0, 0, 0.3f}, "VEC3");
  const int target1 = g.AddFloats({0.1f, 0, 0, 0.2f, 0, 0, 0.3f, 0, 0}, "VEC3");
  const int joints_accessor = g.AddFloats({0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0}, "VEC4");
  const int weights_accessor = g.AddFloats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
  g.json["meshes"] = Json::array(
      {{{"name", "Tri"},
        {"primitives",
         {{{"attributes", {{"POSITION", positions}, {"WEIGHTS_0", weights_accessor}}},
           {"targets", {{{"POSITION", target0}}, {{"POSITION", target1}}}}}}},
        {"weights", {0, 0}},
        {"extras", {{"targetNames", {"smile", "blink"}}}}}});
  (void)joints_accessor;
  std::vector<float> inverse_bind;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 16; ++i) inverse_bind.push_back(i % 5 == 0 ? 1.0f : 0.0f);
  }
  const int ibm = g.AddFloats(inverse_bind, "MAT4");
  g.json["accessors"][static_cast<size_t>(ibm)]["count"] = 3;
  g.json["skins"] = Json::array({{{"joints", {0, 1, 2}}, {"inverseBindMatrices", ibm}}});
  // The animation: 61 keys at 30 fps.
  std::vector<float> times, rotation, translation, weights;
  for (int f = 0; f <= 60; ++f) {
    times.push_back(static_cast<float>(f / 30.0));
    const double half = ArmAngle(f) * 3.14159265358979323846 / 360;
    rotation.insert(rotation.end(), {0, 0, static_cast<float>(std::sin(half)),
                                     static_cast<float>(std::cos(half))});
    translation.insert(translation.end(), {static_cast<float>(0.01 * f), 1, 0});
    weights.insert(weights.end(), {static_cast<float>(f / 60.0), static_cast<float>(1 - f / 60.0)});
  }
  const int input = g.AddFloats(times, "SCALAR", true);
  const int rot = g.AddFloats(rotation, "VEC4");
  const int tr = g.AddFloats(translation, "VEC3");
  const int wt = g.AddFloats(weights, "SCALAR");
  g.json["animations"] = Json::array(
      {{{"name", "Wave"},
        {"channels",
         {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "rotation"}}}},
          {{"sampler", 1}, {"target", {{"node", 0}, {"path", "translation"}}}},
          {{"sampler", 2}, {"target", {{"node", 3}, {"path", "weights"}}}, {"extras", {{"k", 1}}}}}},
        {"samplers",
         {{{"input", input}, {"output", rot}, {"interpolation", interpolation}},
          {{"input", input}, {"output", tr}, {"interpolation", interpolation}},
          {{"input", input}, {"output", wt}, {"interpolation", interpolation}}}},
        {"extras", {{"take", "wave"}}}}});
  return g;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_TESTING_GLTF_BUILDER_H_

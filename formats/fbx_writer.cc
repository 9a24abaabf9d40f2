// A retimed take written into its FBX file (formats/fbx_scene.h, WriteFbxRetimed).
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/fbx_rig.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/fbx_scene.h"

namespace koma::formats {
namespace {

constexpr int64_t kConstantKey = 0x00000002;  // KeyAttrFlags: eInterpolationConstant

FbxNode* TopLevel(FbxDocument& document, std::string_view name) {
  for (FbxNode& node : document.nodes) {
    if (node.name == name) return &node;
  }
  return nullptr;
}

// Sets the values of the P record `name` in `owner`'s Properties70 (when it has one).
void SetProperty(FbxNode* owner, std::string_view name, const std::vector<FbxProperty>& values) {
  FbxNode* block = owner == nullptr ? nullptr : owner->Child("Properties70");
  if (block == nullptr) return;
  for (FbxNode& p : block->children) {
    if (p.properties.size() < 4 || p.properties[0].bytes != name) continue;
    p.properties.resize(4);
    p.properties.insert(p.properties.end(), values.begin(), values.end());
    p.changed = true;
  }
}

// The float holding two 16-bit tangent weights of 1/3 (x 10,000), as the SDK packs them.
double DefaultWeights() {
  const uint32_t bits = 3333u | (3333u << 16);
  float packed;
  std::memcpy(&packed, &bits, 4);
  return packed;
}

void ReplaceArray(FbxNode& curve, const char* name, FbxProperty property) {
  FbxNode* node = curve.Child(name);
  if (node == nullptr) {
    curve.children.emplace_back();
    node = &curve.children.back();
    node->name = name;
  }
  node->properties = {std::move(property)};
  node->changed = true;
}

// TimeMode for `fps`, or 14 (custom) when none has it.
int64_t TimeModeFor(double fps) {
  for (int64_t mode = 1; mode <= 18; ++mode) {
    if (mode != 14 && std::fabs(FbxTimeModeFps(mode, 0) - fps) < 1e-6) return mode;
  }
  return 14;
}

}  // namespace

absl::StatusOr<std::string> WriteFbxRetimed(FbxDocument document, const FbxTakeRig& rig,
                                            const std::vector<int64_t>& sample_ticks,
                                            double output_fps) {
  if (sample_ticks.empty() || !(output_fps > 0)) {
    return absl::InternalError("FBX writer: no output frames");
  }
  const int64_t start = rig.take.start;
  std::vector<int64_t> times(sample_ticks.size());
  for (size_t k = 0; k < times.size(); ++k) {
    times[k] = start + std::llround(static_cast<double>(k) *
                                    static_cast<double>(kFbxTicksPerSecond) / output_fps);
  }
  FbxNode* objects = TopLevel(document, "Objects");
  if (objects == nullptr) return absl::InternalError("FBX writer: no Objects");
  std::map<int64_t, size_t> curve_of;  // AnimationCurve id -> the rig's curve
  for (size_t c = 0; c < rig.curve_ids.size(); ++c) curve_of[rig.curve_ids[c]] = c;
  // Every rewritten curve has the same key times: encoded (compressed, as the file's arrays
  // mostly are) once, raw once, and shared.
  const FbxProperty times_compressed = FbxProperty::EncodedIntegerArray('l', times, true);
  const FbxProperty times_raw = FbxProperty::EncodedIntegerArray('l', times, false);
  StopPoll stop(/*steps_between_checks=*/1 << 14);  // keys written
  for (FbxNode& object : objects->children) {
    if (object.name != "AnimationCurve" || object.properties.empty()) continue;
    const auto found = curve_of.find(object.properties[0].integer);
    if (found == curve_of.end()) continue;  // another take's or layer's: as it was
    const size_t c = found->second;
    if (stop.Stop(static_cast<int64_t>(times.size()))) return stop.status();
    const FbxKeyCurve& curve = rig.rig.curves[c];
    std::vector<double> values(sample_ticks.size());
    size_t cursor = 0;
    for (size_t k = 0; k < values.size(); ++k) {
      values[k] = static_cast<float>(EvaluateFbxCurveFrom(curve, sample_ticks[k], cursor));
    }
    const FbxNode* old_times = object.Child("KeyTime");
    const bool compress = old_times != nullptr && !old_times->properties.empty() &&
                          old_times->properties[0].encoding == 1;
    ReplaceArray(object, "KeyTime", compress ? times_compressed : times_raw);
    ReplaceArray(object, "KeyValueFloat", FbxProperty::DoubleArray('f', values, compress));
    ReplaceArray(object, "KeyAttrFlags", FbxProperty::IntegerArray('i', {kConstantKey}, false));
    ReplaceArray(object, "KeyAttrDataFloat",
                 FbxProperty::DoubleArray('f', {0.0, 0.0, DefaultWeights(), 0.0}, false));
    ReplaceArray(object, "KeyAttrRefCount",
                 FbxProperty::IntegerArray('i', {static_cast<int64_t>(times.size())}, false));
  }
  const int64_t stop_tick = times.back();
  for (FbxNode& object : objects->children) {
    if (object.name != "AnimationStack" || object.properties.size() < 2) continue;
    const std::string& full = object.properties[1].bytes;
    if (full.substr(0, full.find(std::string("\0\1", 2))) != rig.take.name) continue;
    SetProperty(&object, "LocalStop", {FbxProperty::Int64(stop_tick)});
    SetProperty(&object, "ReferenceStop", {FbxProperty::Int64(stop_tick)});
  }
  if (FbxNode* takes = TopLevel(document, "Takes")) {
    for (FbxNode& t : takes->children) {
      if (t.name != "Take" || t.properties.empty() || t.properties[0].bytes != rig.take.name) {
        continue;
      }
      for (const char* span : {"LocalTime", "ReferenceTime"}) {
        FbxNode* node = t.Child(span);
        if (node == nullptr || node->properties.size() < 2) continue;
        node->properties[1] = FbxProperty::Int64(stop_tick);
        node->changed = true;
      }
    }
  }
  if (std::fabs(output_fps - rig.fps) > 1e-9) {
    FbxNode* global = TopLevel(document, "GlobalSettings");
    const int64_t mode = TimeModeFor(output_fps);
    FbxProperty enum_value;
    enum_value.type = 'I';
    enum_value.integer = mode;
    SetProperty(global, "TimeMode", {enum_value});
    if (mode == 14) {
      FbxProperty rate;
      rate.type = 'D';
      rate.real = output_fps;
      SetProperty(global, "CustomFrameRate", {rate});
    }
  }
  return WriteFbx(document);
}

}  // namespace koma::formats

// Slot attachment timelines of a Spine skeleton: read the names and keys, write new keys.
#include "formats/spine_attachments.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "formats/motion3_internal.h"
#include "formats/json_text.h"

namespace koma::formats {
namespace {

using motion3_internal::Json;
using motion3_internal::PathError;

bool HasSlot(const SpineFile& file, std::string_view slot) {
  const Json& slots = file.document.contains("slots") ? file.document["slots"] : Json();
  if (!slots.is_array()) return false;
  for (const Json& s : slots) {
    if (s.is_object() && s.contains("name") && s["name"].is_string() &&
        s["name"].get<std::string>() == slot) {
      return true;
    }
  }
  return false;
}

std::vector<std::string> SlotNames(const SpineFile& file) {
  std::vector<std::string> names;
  if (!file.document.contains("slots") || !file.document["slots"].is_array()) return names;
  for (const Json& s : file.document["slots"]) {
    if (s.is_object() && s.contains("name") && s["name"].is_string()) {
      names.push_back(s["name"].get<std::string>());
    }
  }
  return names;
}

// Each skin's {slot: {attachment: ...}} object, in file order, for either skins layout.
std::vector<const Json*> SkinSlots(const SpineFile& file) {
  std::vector<const Json*> out;
  if (!file.document.contains("skins")) return out;
  const Json& skins = file.document["skins"];
  if (skins.is_object()) {  // 3.7 and before: {skin: {slot: {...}}}
    for (const auto& [name, slots] : skins.items()) {
      if (slots.is_object()) out.push_back(&slots);
    }
  } else if (skins.is_array()) {  // 3.8, 4.x: [{"name", "attachments": {slot: {...}}}]
    for (const Json& skin : skins) {
      if (skin.is_object() && skin.contains("attachments") && skin["attachments"].is_object()) {
        out.push_back(&skin["attachments"]);
      }
    }
  }
  return out;
}

}  // namespace

absl::StatusOr<std::vector<std::string>> SpineSlotAttachments(const SpineFile& file,
                                                              std::string_view slot) {
  if (!HasSlot(file, slot)) {
    return absl::NotFoundError(absl::StrCat("no slot named \"", std::string(slot), "\" (the skeleton has ",
                                            absl::StrJoin(SlotNames(file), ", "), ")"));
  }
  std::vector<std::string> names;
  const std::string key(slot);
  for (const Json* slots : SkinSlots(file)) {
    if (!slots->contains(key) || !(*slots)[key].is_object()) continue;
    for (const auto& [name, attachment] : (*slots)[key].items()) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  return names;
}

std::string SpineSetupAttachment(const SpineFile& file, std::string_view slot) {
  if (!file.document.contains("slots") || !file.document["slots"].is_array()) return "";
  for (const Json& s : file.document["slots"]) {
    if (s.is_object() && s.contains("name") && s["name"].is_string() &&
        s["name"].get<std::string>() == slot && s.contains("attachment") &&
        s["attachment"].is_string()) {
      return s["attachment"].get<std::string>();
    }
  }
  return "";
}

absl::StatusOr<std::vector<SpineAttachmentKey>> SpineAttachmentKeys(const SpineFile& file,
                                                                    std::string_view animation,
                                                                    std::string_view slot) {
  std::vector<SpineAttachmentKey> keys;
  const Json& doc = file.document;
  const std::string a(animation), s(slot);
  if (!doc.contains("animations") || !doc["animations"].is_object() ||
      !doc["animations"].contains(a) || !doc["animations"][a].is_object()) {
    return keys;
  }
  const Json& anim = doc["animations"][a];
  if (!anim.contains("slots") || !anim["slots"].is_object() || !anim["slots"].contains(s) ||
      !anim["slots"][s].is_object() || !anim["slots"][s].contains("attachment")) {
    return keys;
  }
  const std::string path = absl::StrCat("animations.", a, ".slots.", s, ".attachment");
  const Json& list = anim["slots"][s]["attachment"];
  if (!list.is_array()) return PathError(path, "expected an array of keys");
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string here = absl::StrCat(path, "[", k, "]");
    const Json& key = list[k];
    if (!key.is_object()) return PathError(here, "expected an object");
    SpineAttachmentKey out;
    if (key.contains("time")) {
      if (!key["time"].is_number()) return PathError(here + ".time", "expected a number");
      out.time = key["time"].get<double>();
    }
    if (key.contains("name") && !key["name"].is_null()) {
      if (!key["name"].is_string()) return PathError(here + ".name", "expected a string or null");
      out.name = key["name"].get<std::string>();
    }
    keys.push_back(std::move(out));
  }
  return keys;
}

absl::StatusOr<std::string> WriteSpineAttachments(
    const SpineFile& file, std::string_view animation,
    const std::vector<SpineAttachmentTimeline>& timelines) {
  if (animation.empty()) return absl::InvalidArgumentError("animation: expected a name, got \"\"");
  Json document = file.document;
  const std::string a(animation);
  if (!document.contains("animations") || !document["animations"].is_object()) {
    document["animations"] = Json::object();
  }
  Json& anim = document["animations"][a];
  if (!anim.is_object()) anim = Json::object();
  if (!anim.contains("slots") || !anim["slots"].is_object()) anim["slots"] = Json::object();
  for (size_t t = 0; t < timelines.size(); ++t) {
    const SpineAttachmentTimeline& timeline = timelines[t];
    const std::string path = absl::StrCat("timelines[", t, "]");
    if (!HasSlot(file, timeline.slot)) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".slot: no slot named \"",
                                                     timeline.slot, "\""));
    }
    if (timeline.keys.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(path, ".keys: expected at least 1 key"));
    }
    Json keys = Json::array();
    for (size_t k = 0; k < timeline.keys.size(); ++k) {
      const double time = timeline.keys[k].time;
      if (!std::isfinite(time) || time < 0 || (k > 0 && !(time > timeline.keys[k - 1].time))) {
        return absl::InvalidArgumentError(absl::StrCat(
            path, ".keys[", k, "].time: ", time,
            " must be finite, >= 0 and after the previous key's time"));
      }
      Json key = Json::object();
      if (time != 0 || file.major == 3) key["time"] = JsonNumber(time);
      key["name"] = timeline.keys[k].name;
      keys.push_back(std::move(key));
    }
    Json& slot = anim["slots"][timeline.slot];
    if (!slot.is_object()) slot = Json::object();
    slot["attachment"] = std::move(keys);
  }
  std::string text = document.dump(1, '\t', /*ensure_ascii=*/false, Json::error_handler_t::replace);
  text += '\n';
  return text;
}

}  // namespace koma::formats

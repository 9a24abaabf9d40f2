// Slot attachment timelines (formats/spine_attachments.h) on the real 3.7 export and the
// hand-written 3.8, 4.1 and 4.2 skeletons: names per skin layout, keys read, and
// WriteSpineAttachments writing each version's layout while keeping everything else.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using Json = nlohmann::ordered_json;

SpineFile Parse(const std::string& name) {
  absl::StatusOr<SpineFile> file =
      ParseSpine(ReadTestFile(KOMA_TESTDATA_DIR "/spine/" + name));
  EXPECT_THAT(file.status(), IsOk()) << name;
  return file.ok() ? *std::move(file) : SpineFile{};
}

TEST(SpineAttachmentsTest, NamesOfASlotInEitherSkinLayout) {
  // 3.8 / 4.x: skins is a list of {"name", "attachments"}.
  for (const char* name : {"hero-3.8.json", "hero-4.1.json", "hero-4.2.json"}) {
    const SpineFile file = Parse(name);
    EXPECT_THAT(SpineSlotAttachments(file, "mouth").value(),
                ElementsAre("mouth_closed", "mouth_mid", "mouth_open"))
        << name;
    EXPECT_THAT(SpineSlotAttachments(file, "eyes").value(),
                ElementsAre("eyes_open", "eyes_half", "eyes_closed"))
        << name;
    EXPECT_EQ(SpineSetupAttachment(file, "mouth"), "mouth_closed");
  }
  // 3.7: skins is an object {skin: {slot: {...}}} (Rhubarb's exporter test file).
  const SpineFile matt = Parse("matt-3.7.json");
  EXPECT_THAT(SpineSlotAttachments(matt, "mouth").value(),
              ElementsAre("mouth_a", "mouth_b", "mouth_c", "mouth_d", "mouth_e", "mouth_f",
                          "mouth_g", "mouth_h"));
  const absl::StatusOr<std::vector<std::string>> none = SpineSlotAttachments(matt, "eyes");
  EXPECT_EQ(none.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(none.status().message(), HasSubstr("no slot named \"eyes\" (the skeleton has legs"));
}

TEST(SpineAttachmentsTest, ReadsAnAnimationsKeys) {
  const SpineFile file = Parse("hero-4.1.json");
  const std::vector<SpineAttachmentKey> keys = SpineAttachmentKeys(file, "walk", "eyes").value();
  EXPECT_THAT(keys, ElementsAre(SpineAttachmentKey{0.8, "eyes_closed"},
                                SpineAttachmentKey{0.9, "eyes_open"}));
  EXPECT_TRUE(SpineAttachmentKeys(file, "walk", "mouth").value().empty());
  EXPECT_TRUE(SpineAttachmentKeys(file, "talk", "eyes").value().empty());
  SpineFile bad = file;
  bad.document["animations"]["walk"]["slots"]["eyes"]["attachment"][1]["name"] = 3;
  EXPECT_THAT(SpineAttachmentKeys(bad, "walk", "eyes").status().message(),
              HasSubstr("animations.walk.slots.eyes.attachment[1].name: expected a string or null"));
}

const std::vector<SpineAttachmentTimeline> kMouthAndEyes = {
    {"mouth", {{0.0, "mouth_closed"}, {1.0 / 24, "mouth_open"}, {4.0 / 24, "mouth_mid"}}},
    {"eyes", {{0.0, "eyes_open"}, {0.5, "eyes_closed"}, {0.625, "eyes_half"}}},
};

// The written timeline as JSON in the file's version: 3.x writes every time, 4.x omits 0.
Json Expected(const SpineAttachmentTimeline& timeline, int major) {
  Json keys = Json::array();
  for (const SpineAttachmentKey& key : timeline.keys) {
    Json k = Json::object();
    if (key.time != 0 || major == 3) k["time"] = key.time;
    k["name"] = key.name;
    keys.push_back(k);
  }
  return keys;
}

TEST(SpineAttachmentsTest, WritesEachVersionAndKeepsEverythingElse) {
  for (const char* name : {"hero-3.8.json", "hero-4.1.json", "hero-4.2.json"}) {
    SCOPED_TRACE(name);
    const SpineFile file = Parse(name);
    for (const char* animation : {"walk", "talk"}) {  // existing, new
      SCOPED_TRACE(animation);
      const absl::StatusOr<std::string> text =
          WriteSpineAttachments(file, animation, kMouthAndEyes);
      ASSERT_THAT(text.status(), IsOk());
      Json written = Json::parse(*text);
      Json& slots = written["animations"][animation]["slots"];
      for (const SpineAttachmentTimeline& timeline : kMouthAndEyes) {
        EXPECT_EQ(slots[timeline.slot]["attachment"], Expected(timeline, file.major));
        // Only the attachment timeline is replaced: the slot's other timelines stay.
        slots[timeline.slot].erase("attachment");
        if (slots[timeline.slot].empty()) slots.erase(timeline.slot);
      }
      // Without the written timelines, the document is the input (a new animation: gone).
      Json input = Json::parse(ReadTestFile(std::string(KOMA_TESTDATA_DIR "/spine/") + name));
      Json& in_anim = input["animations"][animation];
      if (in_anim.is_null()) {
        EXPECT_TRUE(slots.empty());
        written["animations"].erase(animation);
        input["animations"].erase(animation);
      } else {
        if (in_anim.contains("slots")) {
          for (const SpineAttachmentTimeline& timeline : kMouthAndEyes) {
            if (!in_anim["slots"].contains(timeline.slot)) continue;
            in_anim["slots"][timeline.slot].erase("attachment");
            if (in_anim["slots"][timeline.slot].empty()) in_anim["slots"].erase(timeline.slot);
          }
        } else {
          EXPECT_TRUE(slots.empty());
          written["animations"][animation].erase("slots");
        }
      }
      EXPECT_EQ(written, input);
      // And it still parses, with the same bone curves.
      const absl::StatusOr<SpineFile> again = ParseSpine(*text);
      ASSERT_THAT(again.status(), IsOk());
      ASSERT_GE(again->animations.size(), file.animations.size());
      for (size_t a = 0; a < file.animations.size(); ++a) {
        EXPECT_EQ(again->animations[a].curves.curves.size(),
                  file.animations[a].curves.curves.size());
      }
      EXPECT_EQ(SpineAttachmentKeys(*again, animation, "mouth").value(), kMouthAndEyes[0].keys);
    }
  }
}

TEST(SpineAttachmentsTest, Writes37Layout) {
  const SpineFile file = Parse("matt-3.7.json");
  const std::vector<SpineAttachmentTimeline> mouth = {
      {"mouth", {{0.0, "mouth_a"}, {0.25, "mouth_c"}}}};
  const Json written = Json::parse(WriteSpineAttachments(file, "walk", mouth).value());
  EXPECT_EQ(written["animations"]["walk"]["slots"]["mouth"]["attachment"],
            Json::parse(R"([{"time": 0, "name": "mouth_a"}, {"time": 0.25, "name": "mouth_c"}])"));
  EXPECT_EQ(written["skeleton"]["spine"], "3.7.94");
}

TEST(SpineAttachmentsTest, RefusesBadTimelines) {
  const SpineFile file = Parse("hero-4.1.json");
  EXPECT_THAT(WriteSpineAttachments(file, "walk", {{"nose", {{0, "x"}}}}).status().message(),
              HasSubstr("timelines[0].slot: no slot named \"nose\""));
  EXPECT_THAT(WriteSpineAttachments(file, "walk", {{"mouth", {}}}).status().message(),
              HasSubstr("timelines[0].keys: expected at least 1 key"));
  EXPECT_THAT(
      WriteSpineAttachments(file, "walk", {{"mouth", {{0.5, "a"}, {0.5, "b"}}}}).status().message(),
      HasSubstr("timelines[0].keys[1].time: 0.5 must be finite, >= 0 and after"));
  EXPECT_THAT(WriteSpineAttachments(file, "", {}).status().message(),
              HasSubstr("animation: expected a name"));
}

}  // namespace
}  // namespace koma::formats

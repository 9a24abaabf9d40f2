// formats/gltf.h: reading the test arm (tests/testing/gltf_builder.h) as GLB and .gltf, writing
// it back with and without replaced animations, and what is kept.
#include "formats/gltf.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "formats/gltf_internal.h"
#include "tests/testing/gltf_builder.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::ArmGltf;
using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::Eq;
using ::testing::HasSubstr;
using Json = nlohmann::ordered_json;

// The JSON of a written file (GLB or .gltf).
Json JsonOf(const std::string& bytes) {
  if (IsGlb(bytes)) {
    absl::StatusOr<GlbChunks> chunks = SplitGlb(bytes);
    EXPECT_THAT(chunks.status(), IsOk());
    return Json::parse(chunks->json);
  }
  return Json::parse(bytes);
}

// The bytes accessor `index` covers in a written file.
std::string AccessorBytes(const GltfDocument& document, int index) {
  const Json& accessor = document.json["accessors"][static_cast<size_t>(index)];
  const Json& view = document.json["bufferViews"][accessor["bufferView"].get<size_t>()];
  return document.buffers[view["buffer"].get<size_t>()].substr(
      view.value("byteOffset", size_t{0}) + accessor.value("byteOffset", size_t{0}),
      view["byteLength"].get<size_t>());
}

TEST(GltfReadTest, ReadsTheArmAsGlbAndAsGltf) {
  for (const bool glb : {true, false}) {
    const std::string bytes = glb ? ArmGltf().Glb() : ArmGltf().GltfText();
    ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(bytes));
    EXPECT_EQ(doc.binary, glb);
    EXPECT_THAT(doc.node_names, ElementsAre("Hips", "Arm", "Hand", "Body"));
    EXPECT_THAT(doc.joints, ElementsAre(0, 1, 2));  // the skin's, not the mesh node
    EXPECT_THAT(doc.hierarchy.parent, ElementsAre(-1, 0, 1, -1));
    EXPECT_THAT(doc.hierarchy.order, ElementsAre(0, 1, 2, 3));
    ASSERT_EQ(doc.animations.size(), 1u);
    const GltfClip& clip = doc.animations[0].clip;
    EXPECT_EQ(doc.animations[0].name, "Wave");
    ASSERT_EQ(clip.channels.size(), 3u);
    EXPECT_EQ(clip.channels[0].path, GltfPath::kRotation);
    EXPECT_EQ(clip.channels[2].path, GltfPath::kWeights);
    EXPECT_EQ(clip.samplers[2].width, 2);  // two morph targets
    EXPECT_EQ(clip.samplers[0].times.size(), 61u);
    EXPECT_EQ(GltfAutoSourceFps(clip), 30);
    EXPECT_EQ(GltfFrameCount(clip, 30), 61);
  }
}

TEST(GltfWriteTest, NothingReplacedKeepsTheDocumentAndTheBytes) {
  for (const bool glb : {true, false}) {
    const std::string bytes = glb ? ArmGltf().Glb() : ArmGltf().GltfText();
    ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(bytes));
    ASSERT_OK_AND_ASSIGN(const std::string written, WriteGltf(doc, {}, false));
    EXPECT_EQ(JsonOf(written), JsonOf(bytes));
    ASSERT_OK_AND_ASSIGN(const GltfDocument again, ReadGltf(written));
    EXPECT_EQ(again.buffers, doc.buffers);
    if (glb) {
      EXPECT_EQ(written, bytes);  // byte for byte: same JSON text, same BIN
    }
  }
}

// A file with no "animations" member (a mesh, a pose): writing it back adds and drops that
// member, which once left the writer holding references into moved JSON members (a fuzz
// finding; under ASan this test failed with a heap-use-after-free).
TEST(GltfWriteTest, AFileWithoutAnimationsWritesBackAsItWas) {
  Json json = Json::parse(ArmGltf().GltfText());
  json.erase("animations");
  const std::string bytes = json.dump(2) + "\n";
  ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(bytes));
  EXPECT_TRUE(doc.animations.empty());
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteGltf(doc, {}, false));
  EXPECT_EQ(JsonOf(written), json);
  EXPECT_FALSE(JsonOf(written).contains("animations"));
}

GltfAnimationKeys TwoKeys(const GltfDocument& doc) {
  GltfAnimationKeys keys;
  keys.times = {0, 1.0 / 3};
  for (const GltfChannel& channel : doc.animations[0].clip.channels) {
    const int width = doc.animations[0].clip.samplers[static_cast<size_t>(channel.sampler)].width;
    std::vector<double> values;
    for (int k = 0; k < 2; ++k) {
      for (int i = 0; i < width; ++i) values.push_back(k * 10 + i);
    }
    keys.values.push_back(values);
  }
  return keys;
}

TEST(GltfWriteTest, ReplacedAnimationGetsStepKeysAndItsOldDataIsDropped) {
  for (const bool glb : {true, false}) {
    const std::string bytes = glb ? ArmGltf().Glb() : ArmGltf().GltfText();
    ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(bytes));
    ASSERT_OK_AND_ASSIGN(const std::string written, WriteGltf(doc, {TwoKeys(doc)}, false));
    ASSERT_OK_AND_ASSIGN(const GltfDocument out, ReadGltf(written));
    const Json before = JsonOf(bytes);
    const Json after = JsonOf(written);
    for (const char* kept : {"asset", "extensionsUsed", "extensions", "extras", "scene", "scenes",
                             "nodes", "meshes", "skins"}) {
      EXPECT_EQ(after[kept], before[kept]) << kept;
    }
    // The arm had 10 accessors, 4 of them the animation's (times, rotation, translation,
    // weights): 6 kept + 1 time accessor + 3 outputs.
    EXPECT_EQ(before["accessors"].size(), 10u);
    EXPECT_EQ(after["accessors"].size(), 10u);
    EXPECT_EQ(after["bufferViews"].size(), 10u);
    // The mesh's data is the same bytes.
    ASSERT_OK_AND_ASSIGN(const GltfDocument source, ReadGltf(bytes));
    for (int a = 0; a < 6; ++a) EXPECT_EQ(AccessorBytes(out, a), AccessorBytes(source, a)) << a;
    // The buffer shrank: 61 keys x (1 + 4 + 3 + 2) floats gone, 2 x 10 added.
    EXPECT_EQ(out.buffers[0].size() + 61 * 10 * 4 - 2 * 10 * 4, source.buffers[0].size());
    const GltfAnimation& animation = out.animations[0];
    EXPECT_EQ(animation.name, "Wave");
    EXPECT_EQ(after["animations"][0]["extras"], before["animations"][0]["extras"]);
    EXPECT_EQ(after["animations"][0]["channels"][2]["extras"],
              before["animations"][0]["channels"][2]["extras"]);
    ASSERT_EQ(animation.clip.channels.size(), 3u);
    for (const GltfSampler& sampler : animation.clip.samplers) {
      EXPECT_EQ(sampler.interpolation, GltfInterpolation::kStep);
      // 1/3 s as a 32-bit float rounded down (never after the frame's time).
      ASSERT_EQ(sampler.times.size(), 2u);
      EXPECT_EQ(sampler.times[0], 0);
      EXPECT_LE(sampler.times[1], 1.0 / 3);
      EXPECT_GT(sampler.times[1], 1.0 / 3 - 1e-7);
    }
    EXPECT_THAT(animation.clip.samplers[1].values, ElementsAre(0, 1, 2, 10, 11, 12));
    EXPECT_THAT(animation.clip.samplers[2].values, ElementsAre(0, 1, 10, 11));
  }
}

TEST(GltfWriteTest, KeepOriginalAddsAnAnimeAnimation) {
  const std::string bytes = ArmGltf().Glb();
  ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(bytes));
  GltfAnimationKeys keys = TwoKeys(doc);
  keys.linear = true;
  ASSERT_OK_AND_ASSIGN(const std::string written, WriteGltf(doc, {keys}, true));
  ASSERT_OK_AND_ASSIGN(const GltfDocument out, ReadGltf(written));
  ASSERT_EQ(out.animations.size(), 2u);
  EXPECT_EQ(out.animations[0].name, "Wave");
  EXPECT_EQ(out.animations[0].clip.samplers[0].values, doc.animations[0].clip.samplers[0].values);
  EXPECT_EQ(out.animations[1].name, "Wave.anime");
  EXPECT_EQ(out.animations[1].clip.samplers[0].interpolation, GltfInterpolation::kLinear);
  EXPECT_EQ(JsonOf(written)["accessors"].size(), 10u + 4u);
}

// One row of the bad-file table: a change to the arm's JSON (or bytes), the message's start.
struct BadFile {
  const char* what;
  std::function<void(Json&)> change;
  const char* message;
};

TEST(GltfReadTest, BadFilesNameTheJsonPath) {
  const std::vector<BadFile> table = {
      {"accessor out of range", [](Json& j) { j["animations"][0]["samplers"][2]["input"] = 99; },
       "animations[0].samplers[2].input: accessor 99 does not exist (10 accessors)"},
      {"elements past the view", [](Json& j) { j["accessors"][6]["count"] = 62; },
       "animations[0].samplers[0].input (accessors[6]): 62 SCALAR elements from byte 0 with "
       "stride 4 pass the end of bufferViews[6] (244 bytes)"},
      {"byteStride shorter than the element",
       [](Json& j) { j["bufferViews"][7]["byteStride"] = 8; },
       "bufferViews[7].byteStride: 8 is shorter than the VEC4 element of accessors[7] (16 bytes)"},
      {"byteStride not a multiple of 4", [](Json& j) { j["bufferViews"][7]["byteStride"] = 6; },
       "bufferViews[7].byteStride: 6 is not a multiple of 4 in 4..252"},
      {"view past the buffer", [](Json& j) { j["bufferViews"][8]["byteLength"] = 100000; },
       "bufferViews[8]: bytes"},
      {"cycle", [](Json& j) { j["nodes"][2]["children"] = {0}; },
       "nodes[0]: is its own ancestor (the node graph has a cycle)"},
      {"two parents", [](Json& j) { j["nodes"][3]["children"] = {2}; },
       "nodes[3].children[0]: node 2 is already a child of node 1"},
      {"missing buffer", [](Json& j) { j["bufferViews"][6]["buffer"] = 3; },
       "bufferViews[6].buffer: buffer 3 does not exist (1 buffers)"},
      {"bad interpolation",
       [](Json& j) { j["animations"][0]["samplers"][1]["interpolation"] = "BEZIER"; },
       "animations[0].samplers[1].interpolation: \"BEZIER\" is not LINEAR, STEP or CUBICSPLINE"},
      {"bad path", [](Json& j) { j["animations"][0]["channels"][1]["target"]["path"] = "pointer"; },
       "animations[0].channels[1].target.path: \"pointer\" is not translation, rotation, scale "
       "or weights"},
      {"channel node out of range",
       [](Json& j) { j["animations"][0]["channels"][0]["target"]["node"] = 40; },
       "animations[0].channels[0].target.node: node 40 does not exist (4 nodes)"},
      {"wrong output type", [](Json& j) { j["animations"][0]["samplers"][0]["output"] = 8; },
       "animations[0].samplers[0].output: 3 components per element, expected 4"},
      {"wrong output count", [](Json& j) { j["accessors"][7]["count"] = 60; },
       "animations[0].samplers[0].output: 60 elements for 61 keys, expected 61"},
      {"external buffer",
       [](Json& j) {
         j["images"] = Json::array({{{"uri", "face.png"}}});
       },
       "images[0].uri: \"face.png\" is an external file"},
      {"a channel tinygltf skips",
       [](Json& j) { j["animations"][0]["channels"][1].erase("sampler"); },
       "animations[0].channels: 3 entries, of which tinygltf read 2: an entry is malformed"},
      // The glTF schema's minItems 1, which the Khronos validator enforces.
      {"an animation without channels",
       [](Json& j) { j["animations"][0]["channels"] = Json::array(); },
       "animations[0].channels: empty: a glTF animation has at least one channel"},
      {"an animation without samplers",
       [](Json& j) { j["animations"][0]["samplers"] = Json::array(); },
       "animations[0].samplers: empty: a glTF animation has at least one sampler"},
      {"an array that is not one",
       [](Json& j) {
         j["animations"] = Json::object({{"take", 1}});
       },
       "animations: not an array"},
      {"skin joint out of range", [](Json& j) { j["skins"][0]["joints"][1] = 17; },
       "skins[0].joints[1]: node 17 does not exist (4 nodes)"},
      {"animated matrix node",
       [](Json& j) {
         j["nodes"][1].erase("translation");
         j["nodes"][1]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.5, 0, 1};
       },
       "animations[0].channels[0].target.node: node 1 has a matrix"},
  };
  for (const BadFile& row : table) {
    testing::TestGltf g = ArmGltf();
    Json json = g.WithBuffer(true);
    row.change(json);
    const std::string bytes = JoinGlb(json.dump(), g.bin);
    EXPECT_THAT(ReadGltf(bytes).status(),
                StatusIs(absl::StatusCode::kInvalidArgument, ::testing::StartsWith(row.message)))
        << row.what;
  }
}

// A .gltf's embedded buffer: a data: URI whose payload is broken is named by its field and
// position, in a message of its own size, not tinygltf's (which quotes the whole URI).
TEST(GltfReadTest, BrokenDataUrisNameThePositionWithoutQuotingTheData) {
  const std::string text = ArmGltf().GltfText();
  const Json good = Json::parse(text);
  const std::string uri = good["buffers"][0]["uri"].get<std::string>();
  const size_t payload = uri.find(";base64,") + 8;
  const auto with_uri = [&](const std::string& changed) {
    Json json = good;
    json["buffers"][0]["uri"] = changed;
    return json.dump();
  };
  std::string bad_character = uri;
  bad_character[payload + 10] = '!';
  const std::string too_short = uri.substr(0, payload + 400);
  const std::string not_base64 = "data:application/octet-stream," + uri.substr(payload);
  const std::string unpadded = uri.substr(0, uri.size() - (uri.back() == '=' ? 1 : 0));
  const struct {
    std::string bytes;
    const char* message;
  } table[] = {
      {with_uri(bad_character), "buffers[0].uri: character 10 of its base64 data (of "},
      {with_uri(too_short),
       "buffers[0].uri: its base64 data decodes to 300 bytes, fewer than "
       "its byteLength "},
      {with_uri(not_base64), "buffers[0].uri: a data: URI of "},
      {with_uri(uri.substr(0, payload + 401)), "buffers[0].uri: its base64 data is 401 characters"},
  };
  for (const auto& row : table) {
    const absl::Status status = ReadGltf(row.bytes).status();
    EXPECT_THAT(status,
                StatusIs(absl::StatusCode::kInvalidArgument, ::testing::StartsWith(row.message)));
    EXPECT_LT(status.message().size(), 200u) << status.message();
  }
  // Unpadded base64 is read, as tinygltf reads it.
  if (unpadded != uri) EXPECT_THAT(ReadGltf(with_uri(unpadded)), IsOk());
}

// Float data patched into the BIN: times out of order, NaN.
TEST(GltfReadTest, BadKeysNameTheSampler) {
  auto patched = [](int key, float value) {
    testing::TestGltf g = ArmGltf();
    const Json view = g.json["bufferViews"][6];
    const size_t at = view["byteOffset"].get<size_t>() + 4 * static_cast<size_t>(key);
    std::memcpy(&g.bin[at], &value, 4);
    return g.Glb();
  };
  EXPECT_THAT(ReadGltf(patched(5, 0.01f)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("animations[0].samplers[0].input: key 5 (0.01 s) is before key "
                                 "4 (0.133333 s): key times must increase")));
  EXPECT_THAT(ReadGltf(patched(3, std::nanf(""))).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("animations[0].samplers[0].input: key 3 is not a finite time")));
  // The Khronos validator's ACCESSOR_ANIMATION_INPUT_NEGATIVE.
  EXPECT_THAT(ReadGltf(patched(0, -0.5f)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("animations[0].samplers[0].input: key 0 is at -0.5 s: glTF key "
                                 "times are >= 0")));
}

TEST(GltfReadTest, TruncatedAndMalformedContainers) {
  const std::string glb = ArmGltf().Glb();
  EXPECT_THAT(ReadGltf(glb.substr(0, glb.size() - 100)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("GLB header: length")));
  std::string chunk = glb;
  chunk[12] = static_cast<char>(0xFF);  // JSON chunk length past the end
  chunk[13] = static_cast<char>(0xFF);
  EXPECT_THAT(ReadGltf(chunk).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("GLB chunk 0 (JSON): 65")));
  EXPECT_THAT(ReadGltf("glTF").status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("GLB header: 4 bytes")));
  // JSON errors in koma's words with the byte offset, not nlohmann's exception ids.
  const absl::Status cut_json = ReadGltf("{\"asset\": ").status();
  EXPECT_THAT(cut_json, StatusIs(absl::StatusCode::kInvalidArgument,
                                 ::testing::StartsWith("invalid JSON at byte ")));
  EXPECT_THAT(cut_json.message(), ::testing::Not(HasSubstr("json.exception")));
  EXPECT_THAT(ReadGltf("").status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("the file is empty: expected a GLB (starting \"glTF\")")));
  EXPECT_THAT(ReadGltf(std::string(100, '[')).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("nested deeper")));
}

TEST(GltfReadTest, ManyNodesWithinAndOverTheLimit) {
  // 100,000 nodes in one chain: read without recursion within a raised limit, refused by the
  // default one.
  Json json = {{"asset", {{"version", "2.0"}}}};
  Json nodes = Json::array();
  for (int i = 0; i < 100000; ++i) {
    Json node = {{"translation", {0, 1, 0}}};
    if (i + 1 < 100000) node["children"] = {i + 1};
    nodes.push_back(node);
  }
  json["nodes"] = nodes;
  const std::string text = json.dump();
  EXPECT_THAT(ReadGltf(text).status(),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("nodes: 100000 nodes exceeds the limit of 65536")));
  GltfReadLimits limits;
  limits.max_nodes = 100000;
  ASSERT_OK_AND_ASSIGN(const GltfDocument doc, ReadGltf(text, limits));
  EXPECT_EQ(doc.hierarchy.order.size(), 100000u);
  EXPECT_EQ(doc.joints.size(), 100000u);  // no skin: every node
}

}  // namespace
}  // namespace koma::formats

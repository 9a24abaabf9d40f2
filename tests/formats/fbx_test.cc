// The binary FBX node tree (formats/fbx.h) on real files (tests/testdata/fbx: Blender 2.79 and
// 2.90, Maya through the FBX SDK) and on broken and hostile ones made here.
#include "formats/fbx.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::HasSubstr;
using ::testing::StartsWith;

std::string ReadTestFile(const std::string& name) {
  std::ifstream in(std::string(KOMA_TESTDATA_DIR) + "/fbx/" + name, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

const char* const kRealFiles[] = {"assimp_animation_with_skeleton.fbx", "assimp_huesitos.fbx",
                                  "ufbx_maya_anim_layers_7500_binary.fbx"};

const FbxNode* Find(const std::vector<FbxNode>& nodes, std::string_view name) {
  for (const FbxNode& node : nodes) {
    if (node.name == name) return &node;
  }
  return nullptr;
}

int CountNamed(const std::vector<FbxNode>& nodes, std::string_view name) {
  int count = 0;
  for (const FbxNode& node : nodes) {
    count += node.name == name;
    count += CountNamed(node.children, name);
  }
  return count;
}

TEST(FbxReadTest, RealFilesReadAndWriteBackByteForByte) {
  for (const char* name : kRealFiles) {
    const std::string bytes = ReadTestFile(name);
    ASSERT_FALSE(bytes.empty()) << name;
    ASSERT_OK_AND_ASSIGN(const FbxDocument document, ReadFbx(bytes));
    EXPECT_TRUE(Find(document.nodes, "Objects") != nullptr) << name;
    EXPECT_TRUE(Find(document.nodes, "Connections") != nullptr) << name;
    EXPECT_GT(CountNamed(document.nodes, "AnimationCurve"), 0) << name;
    EXPECT_EQ(WriteFbx(document), bytes) << name;
  }
}

TEST(FbxReadTest, VersionsAndArraysAsTheToolsWroteThem) {
  ASSERT_OK_AND_ASSIGN(const FbxDocument blender, ReadFbx(ReadTestFile(kRealFiles[0])));
  EXPECT_EQ(blender.version, 7400u);
  ASSERT_OK_AND_ASSIGN(const FbxDocument maya, ReadFbx(ReadTestFile(kRealFiles[2])));
  EXPECT_EQ(maya.version, 7500u);
  // Every AnimationCurve's KeyTime (FBX ticks, l) and KeyValueFloat (f) decode to the same
  // count, the times increasing.
  int curves = 0;
  for (const FbxDocument* document : {&blender, &maya}) {
    const FbxNode* objects = Find(document->nodes, "Objects");
    ASSERT_NE(objects, nullptr);
    for (const FbxNode& node : objects->children) {
      if (node.name != "AnimationCurve") continue;
      const FbxNode* times = node.Child("KeyTime");
      const FbxNode* values = node.Child("KeyValueFloat");
      ASSERT_NE(times, nullptr);
      ASSERT_NE(values, nullptr);
      ASSERT_OK_AND_ASSIGN(const std::vector<int64_t> t, FbxIntegers(times->properties.at(0)));
      ASSERT_OK_AND_ASSIGN(const std::vector<double> v, FbxReals(values->properties.at(0)));
      EXPECT_EQ(t.size(), v.size());
      for (size_t k = 1; k < t.size(); ++k) EXPECT_LT(t[k - 1], t[k]);
      ++curves;
    }
  }
  EXPECT_GT(curves, 50);
}

TEST(FbxWriteTest, AChangedArrayIsWrittenAndReadBack) {
  for (const char* name : kRealFiles) {
    const std::string bytes = ReadTestFile(name);
    ASSERT_OK_AND_ASSIGN(FbxDocument document, ReadFbx(bytes));
    FbxNode* objects = nullptr;
    for (FbxNode& node : document.nodes) {
      if (node.name == "Objects") objects = &node;
    }
    ASSERT_NE(objects, nullptr);
    FbxNode* curve = objects->Child("AnimationCurve");
    ASSERT_NE(curve, nullptr);
    FbxNode* values = curve->Child("KeyValueFloat");
    ASSERT_OK_AND_ASSIGN(std::vector<double> v, FbxReals(values->properties[0]));
    for (double& x : v) x = static_cast<float>(x + 1.0);  // KeyValueFloat holds floats
    const bool compressed = values->properties[0].encoding == 1;
    values->properties[0] = FbxProperty::DoubleArray('f', v, compressed);
    values->changed = true;
    const std::string written = WriteFbx(document);
    EXPECT_NE(written, bytes);
    ASSERT_OK_AND_ASSIGN(const FbxDocument again, ReadFbx(written));
    const FbxNode* again_curve = Find(again.nodes, "Objects")->Child("AnimationCurve");
    ASSERT_OK_AND_ASSIGN(const std::vector<double> read,
                         FbxReals(again_curve->Child("KeyValueFloat")->properties[0]));
    EXPECT_EQ(read, v) << name;
    // Everything else as it was, the footer's layout included (its last 136 bytes).
    EXPECT_EQ(WriteFbx(again), written);
    EXPECT_EQ(written.substr(written.size() - 136), bytes.substr(bytes.size() - 136));
    EXPECT_EQ(CountNamed(again.nodes, "Model"), CountNamed(document.nodes, "Model"));
  }
}

TEST(FbxWriteTest, AnArrayEncodedOnceWritesAsBuiltInEveryCopy) {
  ASSERT_OK_AND_ASSIGN(FbxDocument document, ReadFbx(ReadTestFile("assimp_huesitos.fbx")));
  FbxNode* curve = nullptr;
  for (FbxNode& node : document.nodes) {
    if (node.name == "Objects") curve = node.Child("AnimationCurve");
  }
  ASSERT_NE(curve, nullptr);
  FbxNode* times = curve->Child("KeyTime");
  const std::vector<int64_t> ticks = {0, 1924423250, 3848846500, 5773269750, 7697693000};
  for (const bool compress : {true, false}) {
    times->properties[0] = FbxProperty::IntegerArray('l', ticks, compress);
    times->changed = true;
    const std::string built = WriteFbx(document);
    const FbxProperty encoded = FbxProperty::EncodedIntegerArray('l', ticks, compress);
    times->properties[0] = encoded;  // a copy, sharing the encoded bytes
    const std::string written = WriteFbx(document);
    EXPECT_EQ(written, built) << compress;
    ASSERT_OK_AND_ASSIGN(const FbxDocument again, ReadFbx(written));
    const FbxNode* again_curve = Find(again.nodes, "Objects")->Child("AnimationCurve");
    EXPECT_EQ(again_curve->Child("KeyTime")->properties[0].encoding, compress ? 1u : 0u);
    ASSERT_OK_AND_ASSIGN(const std::vector<int64_t> read,
                         FbxIntegers(again_curve->Child("KeyTime")->properties[0]));
    EXPECT_EQ(read, ticks);
  }
}

// A minimal 7.4 file built here: one top-level node "N" with the given property bytes.
std::string OneNodeFile(const std::string& properties, uint32_t count, uint32_t version = 7400) {
  std::string out("Kaydara FBX Binary  \0\x1a\0", 23);
  out.append(reinterpret_cast<const char*>(&version), 4);
  const uint32_t end = static_cast<uint32_t>(out.size() + 13 + 1 + properties.size());
  const uint32_t length = static_cast<uint32_t>(properties.size());
  out.append(reinterpret_cast<const char*>(&end), 4);
  out.append(reinterpret_cast<const char*>(&count), 4);
  out.append(reinterpret_cast<const char*>(&length), 4);
  out.push_back(1);
  out.push_back('N');
  out += properties;
  out.append(13, '\0');
  return out;
}

std::string ArrayHeader(char type, uint32_t count, uint32_t encoding, uint32_t stored) {
  std::string out(1, type);
  out.append(reinterpret_cast<const char*>(&count), 4);
  out.append(reinterpret_cast<const char*>(&encoding), 4);
  out.append(reinterpret_cast<const char*>(&stored), 4);
  return out;
}

TEST(FbxReadTest, BrokenAndHostileFilesAreRefusedNamingWhere) {
  const std::string good = ReadTestFile(kRealFiles[0]);
  std::string cut = good.substr(0, good.size() / 2);
  std::string bad_end = good;
  const uint32_t huge = 0x7fffffff;
  std::memcpy(&bad_end[27], &huge, 4);  // the first node's end offset
  struct Row {
    std::string bytes;
    absl::StatusCode code;
    const char* message;
  };
  const std::vector<Row> table = {
      {"; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n", absl::StatusCode::kInvalidArgument,
       "an ASCII FBX file"},
      {"PK\3\4 not fbx", absl::StatusCode::kInvalidArgument, "not a binary FBX file"},
      {OneNodeFile("", 0, 6100), absl::StatusCode::kInvalidArgument, "FBX version 6.1 (6100)"},
      {cut, absl::StatusCode::kInvalidArgument, "byte "},
      {bad_end, absl::StatusCode::kInvalidArgument,
       "byte 27 (FBXHeaderExtension): the node record's end offset 2147483647 is outside"},
      {OneNodeFile("Q", 1), absl::StatusCode::kInvalidArgument, "unknown type byte 0x51"},
      {OneNodeFile(std::string("S\xff\xff\0\0", 5), 1), absl::StatusCode::kInvalidArgument,
       "pass the"},
      // A zip bomb: 2^31 doubles claimed in 10 bytes, refused before anything inflates.
      {OneNodeFile(ArrayHeader('d', 0x80000000u, 1, 10) + std::string(10, 'x'), 1),
       absl::StatusCode::kResourceExhausted, "an array of 2147483648 elements"},
      {OneNodeFile(ArrayHeader('d', 4, 0, 8) + std::string(8, '\0'), 1),
       absl::StatusCode::kInvalidArgument, "a raw array of 4 elements in 8 bytes"},
      {OneNodeFile(ArrayHeader('d', 1, 7, 8) + std::string(8, '\0'), 1),
       absl::StatusCode::kInvalidArgument, "array encoding 7"},
      {OneNodeFile(std::string("I\1\0\0\0", 5), 9), absl::StatusCode::kInvalidArgument,
       "9 properties in 5 bytes"},
  };
  for (const Row& row : table) {
    EXPECT_THAT(ReadFbx(row.bytes).status(), StatusIs(row.code, HasSubstr(row.message)))
        << row.message;
  }
}

TEST(FbxReadTest, DeepNestingIsRefusedBeforeTheStackGoes) {
  // 100,000 nested nodes "N", each the only child of the one before.
  const int depth = 100000;
  std::string out("Kaydara FBX Binary  \0\x1a\0", 23);
  const uint32_t version = 7400;
  out.append(reinterpret_cast<const char*>(&version), 4);
  const size_t record = 13 + 1;
  const size_t total = out.size() + static_cast<size_t>(depth) * (record + 13) + 13;
  for (int i = 0; i < depth; ++i) {
    const uint32_t end = static_cast<uint32_t>(total - 13 - static_cast<size_t>(i) * 13);
    const uint32_t zero = 0;
    out.append(reinterpret_cast<const char*>(&end), 4);
    out.append(reinterpret_cast<const char*>(&zero), 4);
    out.append(reinterpret_cast<const char*>(&zero), 4);
    out.push_back(1);
    out.push_back('N');
  }
  for (int i = 0; i <= depth; ++i) out.append(13, '\0');
  EXPECT_THAT(ReadFbx(out).status(),
              StatusIs(absl::StatusCode::kResourceExhausted, HasSubstr("nested deeper than 32")));
}

TEST(FbxReadTest, ABrokenZlibArrayIsNamedWhenRead) {
  const std::string file =
      OneNodeFile(ArrayHeader('d', 2, 1, 6) + std::string("\x78\x9c\xff\xff\xff\xff", 6), 1);
  ASSERT_OK_AND_ASSIGN(const FbxDocument document, ReadFbx(file));
  EXPECT_THAT(FbxReals(document.nodes.at(0).properties.at(0)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, StartsWith("an array of 2 'd'")));
  EXPECT_THAT(FbxIntegers(document.nodes.at(0).properties.at(0)).status(),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("integers")));
}

}  // namespace
}  // namespace koma::formats

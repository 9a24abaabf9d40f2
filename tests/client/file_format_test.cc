#include "client/file_format.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "client/skeletal_file_formats.h"
#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::Eq;

TEST(FileFormatTest, Sniffs) {
  EXPECT_EQ(SniffFormat("HIERARCHY\nROOT Hips"), FormatId::kBvh);
  EXPECT_EQ(SniffFormat("\xEF\xBB\xBF  \r\nHIERARCHY"), FormatId::kBvh);
  EXPECT_EQ(SniffFormat(" {\"Version\": 3}"), FormatId::kMotion3);
  EXPECT_EQ(SniffFormat("frame,ParamA\n0,1\n"), FormatId::kCsv);
  EXPECT_EQ(SniffFormat("\xEF\xBB\xBF\"frame\";\"A\"\n"), FormatId::kCsv);
  EXPECT_EQ(SniffFormat("frames,x"), FormatId::kUnknown);
  EXPECT_EQ(SniffFormat(""), FormatId::kUnknown);
  EXPECT_EQ(FormatFromName("a/B.BVH"), FormatId::kBvh);
  EXPECT_EQ(FormatFromName("x.motion3.json"), FormatId::kMotion3);
  EXPECT_EQ(FormatFromName("x.Csv"), FormatId::kCsv);
  EXPECT_EQ(FormatFromName("-"), FormatId::kUnknown);
  for (const char* name : {"a.glb", "a.GLTF", "avatar.vrm", "walk.vrma"}) {
    EXPECT_EQ(FormatFromName(name), FormatId::kGltf) << name;
  }
  EXPECT_EQ(SniffFormat("glTF\x02\0\0\0"), FormatId::kGltf);
  EXPECT_EQ(SniffFormat(" {\"asset\":{\"version\":\"2.0\"},\"nodes\":[]}"), FormatId::kGltf);
  EXPECT_EQ(SniffFormat("{\"Version\":3,\"Curves\":[],\"asset\":1}"), FormatId::kMotion3);
}

TEST(FileFormatTest, NamesTheWrongFormat) {
  EXPECT_THAT(CheckInputFormat("walk.bvh", "HIERARCHY\n", "curves"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("walk.bvh is a BVH file, not motion3.json or CSV: `koma curves` reads "
                          "Live2D motion3.json or per-frame CSV; retime BVH clips with `koma "
                          "skeletal`")));
  EXPECT_THAT(CheckInputFormat("-", "{}", "skeletal"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("standard input is a motion3.json file, not BVH, glTF or FBX: `koma "
                          "skeletal` reads BVH motion capture, glTF 2.0 / VRM and binary FBX; "
                          "retime curves with `koma curves` or `koma lipblink`")));
  EXPECT_THAT(CheckInputFormat("a.glb", "glTF\x02", "curves"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("a.glb is a glTF file, not motion3.json or CSV: `koma curves` reads "
                          "Live2D motion3.json or per-frame CSV; retime glTF files with `koma "
                          "skeletal`")));
  EXPECT_THAT(CheckInputFormat("a.gltf", "{\"asset\": {\"version\": \"2.0\"}}", "skeletal"), IsOk());
  EXPECT_THAT(
      CheckInputFormat("x.csv", "frame,a\n0,1\n", "skeletal"),
      StatusIs(absl::StatusCode::kInvalidArgument, ::testing::StartsWith("x.csv is a CSV file")));
  EXPECT_THAT(CheckInputFormat("x.bvh", "HIERARCHY", "skeletal"), IsOk());
  EXPECT_THAT(CheckInputFormat("x.json", "{}", "lipblink"), IsOk());
  EXPECT_THAT(CheckInputFormat("x", "garbage", "curves"), IsOk());  // the parser names it
  EXPECT_THAT(CheckInputFormat("take.fbx", "Kaydara FBX Binary  ", "lipblink --animation"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("take.fbx is a FBX file, not motion3.json or CSV: `koma lipblink "
                          "--animation` reads Live2D motion3.json or per-frame CSV; retime FBX "
                          "takes with `koma skeletal`")));
  // A Spine skeleton is read by curves and lipblink; skeletal names it (the table's Spine row).
  const char* const skeleton = "{\"skeleton\": {\"spine\": \"4.2\"}, \"bones\": []}";
  EXPECT_THAT(CheckInputFormat("hero.json", skeleton, "curves"), IsOk());
  EXPECT_THAT(CheckInputFormat("hero.json", skeleton, "lipblink"), IsOk());
  EXPECT_THAT(CheckInputFormat("hero.json", skeleton, "skeletal"),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       Eq("hero.json is a Spine JSON file, not BVH, glTF or FBX: `koma skeletal` "
                          "reads BVH motion capture, glTF 2.0 / VRM and binary FBX; retime Spine "
                          "animations with `koma curves` or `koma lipblink`")));
}

// The formats the server reads whole have their functions in the client, found by name or
// by bytes; a BVH has none (the client decodes it).
TEST(FileFormatTest, SkeletalFileFormatsCoverTheTable) {
  for (const formats::FormatRow& row : formats::FormatTable()) {
    for (std::string_view extension : row.extensions) {
      const SkeletalFileFormat* file = SkeletalFileFormatOf("take" + std::string(extension));
      if (row.sent_whole) {
        ASSERT_NE(file, nullptr) << extension;
        EXPECT_EQ(file->id, row.id) << extension;
      } else {
        EXPECT_EQ(file, nullptr) << extension;
      }
    }
  }
  const std::string glb = std::string("glTF\x02\0\0\0", 8);
  ASSERT_NE(SkeletalFileFormatOf("-", &glb), nullptr);
  EXPECT_EQ(SkeletalFileFormatOf("-", &glb)->id, FormatId::kGltf);
  const std::string bvh = "HIERARCHY\n";
  EXPECT_EQ(SkeletalFileFormatOf("walk.bvh", &bvh), nullptr);
}

}  // namespace
}  // namespace koma::client

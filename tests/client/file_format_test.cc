#include "client/file_format.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::Eq;

TEST(FileFormatTest, Sniffs) {
  EXPECT_EQ(SniffFormat("HIERARCHY\nROOT Hips"), FileFormat::kBvh);
  EXPECT_EQ(SniffFormat("\xEF\xBB\xBF  \r\nHIERARCHY"), FileFormat::kBvh);
  EXPECT_EQ(SniffFormat(" {\"Version\": 3}"), FileFormat::kMotion3);
  EXPECT_EQ(SniffFormat("frame,ParamA\n0,1\n"), FileFormat::kCsv);
  EXPECT_EQ(SniffFormat("\xEF\xBB\xBF\"frame\";\"A\"\n"), FileFormat::kCsv);
  EXPECT_EQ(SniffFormat("frames,x"), FileFormat::kUnknown);
  EXPECT_EQ(SniffFormat(""), FileFormat::kUnknown);
  EXPECT_EQ(FormatFromName("a/B.BVH"), FileFormat::kBvh);
  EXPECT_EQ(FormatFromName("x.motion3.json"), FileFormat::kMotion3);
  EXPECT_EQ(FormatFromName("x.Csv"), FileFormat::kCsv);
  EXPECT_EQ(FormatFromName("-"), FileFormat::kUnknown);
  for (const char* name : {"a.glb", "a.GLTF", "avatar.vrm", "walk.vrma"}) {
    EXPECT_EQ(FormatFromName(name), FileFormat::kGltf) << name;
  }
  EXPECT_EQ(SniffFormat("glTF\x02\0\0\0"), FileFormat::kGltf);
  EXPECT_EQ(SniffFormat(" {\"asset\":{\"version\":\"2.0\"},\"nodes\":[]}"), FileFormat::kGltf);
  EXPECT_EQ(SniffFormat("{\"Version\":3,\"Curves\":[],\"asset\":1}"), FileFormat::kMotion3);
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
}

}  // namespace
}  // namespace koma::client

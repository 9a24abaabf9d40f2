// DiscoverInputs and TimingPathFor: which files a batch takes and where their outputs go.
#include "client/batch/batch_inputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/batch/scratch_folder.h"
#include "tests/testing/status_matchers.h"

namespace koma::client::batch {
namespace {

namespace fs = std::filesystem;
using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// A scratch folder, removed with the test.
class Tree : public ScratchFolder {
 protected:
  static std::vector<std::string> Relatives(const std::vector<BatchItem>& items) {
    std::vector<std::string> relatives;
    for (const BatchItem& item : items) relatives.push_back(item.relative);
    return relatives;
  }
};

TEST_F(Tree, FolderIsSearchedByExtensionInPathOrderAndMirrored) {
  Touch("in/x.bvh");
  Touch("in/sub/y.BVH");  // any case
  Touch("in/sub/deeper/a.bvh");
  Touch("in/notes.txt");
  Touch("in/x.bvh.tmp");
  ASSERT_OK_AND_ASSIGN(std::vector<BatchItem> items,
                       DiscoverInputs({P("in")}, {".bvh"}, P("out"), /*with_timing=*/true,
                                      /*with_report=*/true));
  EXPECT_THAT(Relatives(items), ElementsAre("sub/deeper/a.bvh", "sub/y.BVH", "x.bvh"));
  EXPECT_EQ(items[1].input, P("in/sub/y.BVH"));
  EXPECT_EQ(items[1].output, P("out/sub/y.BVH"));
  EXPECT_EQ(items[1].timing, P("out/sub/y.timing.csv"));
  EXPECT_EQ(items[1].report, P("out/sub/y.report.html"));
}

TEST_F(Tree, FilesKeepTheirNameAndAreTakenOnce) {
  const std::string a = Touch("one/a.bvh");
  const std::string b = Touch("two/b.anything");  // named directly: taken whatever its name
  ASSERT_OK_AND_ASSIGN(std::vector<BatchItem> items,
                       DiscoverInputs({a, b, a, P("one")}, {".bvh"}, P("out"), false));
  EXPECT_THAT(Relatives(items), ElementsAre("a.bvh", "b.anything"));
  EXPECT_EQ(items[0].output, P("out/a.bvh"));
  EXPECT_EQ(items[0].timing, "");
}

TEST_F(Tree, OutputFolderInsideTheInputFolderIsNotSearched) {
  Touch("in/x.bvh");
  Touch("in/out/x.bvh");  // an earlier run's output
  ASSERT_OK_AND_ASSIGN(std::vector<BatchItem> items,
                       DiscoverInputs({P("in")}, {".bvh"}, P("in/out"), false));
  EXPECT_THAT(Relatives(items), ElementsAre("x.bvh"));
}

TEST_F(Tree, ListsNameFilesAndFoldersSkippingBlanksAndComments) {
  Touch("in/a.csv");
  Touch("in/f/b.motion3.json");
  Touch("list.txt", "# picked\n" + P("in/a.csv") + "\n\n  " + P("in/f") + "  \n");
  ASSERT_OK_AND_ASSIGN(
      std::vector<BatchItem> items,
      DiscoverInputs({"@" + P("list.txt")}, {".motion3.json", ".csv"}, P("out"), false));
  EXPECT_THAT(Relatives(items), ElementsAre("a.csv", "b.motion3.json"));
}

TEST_F(Tree, MissingPathsAreNamedWithTheirListLine) {
  Touch("list.txt", P("in/a.bvh") + "\n");
  EXPECT_THAT(DiscoverInputs({P("nowhere")}, {".bvh"}, P("out"), false),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("input: " + P("nowhere") + ": no such file or folder")));
  EXPECT_THAT(DiscoverInputs({"@" + P("list.txt")}, {".bvh"}, P("out"), false),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr(P("list.txt") + ":1: " + P("in/a.bvh"))));
  EXPECT_THAT(DiscoverInputs({"@" + P("no_list.txt")}, {".bvh"}, P("out"), false),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("cannot read the list")));
}

TEST_F(Tree, TwoInputsWritingOneFileAreRefused) {
  const std::string a = Touch("one/x.bvh");
  const std::string b = Touch("two/x.bvh");
  EXPECT_THAT(DiscoverInputs({a, b}, {".bvh"}, P("out"), false),
              StatusIs(absl::StatusCode::kInvalidArgument,
                       HasSubstr("inputs " + a + " and " + b + " would both write")));
  // x.motion3.json and x.csv: different outputs, but one timing sheet x.timing.csv.
  Touch("c/x.motion3.json");
  Touch("c/x.csv");
  EXPECT_THAT(DiscoverInputs({P("c")}, {".motion3.json", ".csv"}, P("out"), false), IsOk());
  EXPECT_THAT(DiscoverInputs({P("c")}, {".motion3.json", ".csv"}, P("out"), true),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("x.timing.csv")));
  EXPECT_THAT(DiscoverInputs({P("c")}, {".motion3.json", ".csv"}, P("out"), false, true),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("x.report.html")));
}

TEST(TimingPathFor, ReplacesTheInputExtension) {
  const std::vector<std::string> curves = {".motion3.json", ".csv"};
  EXPECT_EQ(TimingPathFor("a/b.bvh", {".bvh"}), "a/b.timing.csv");
  EXPECT_EQ(TimingPathFor("a/b.BVH", {".bvh"}), "a/b.timing.csv");
  EXPECT_EQ(TimingPathFor("a/b.motion3.json", curves), "a/b.timing.csv");
  EXPECT_EQ(TimingPathFor("a/b.csv", curves), "a/b.timing.csv");
  EXPECT_EQ(TimingPathFor("a/b.json", curves), "a/b.json.timing.csv");
  EXPECT_EQ(TimingPathFor("noext", {".bvh"}), "noext.timing.csv");
  EXPECT_EQ(ReportPathFor("a/b.motion3.json", curves), "a/b.report.html");
}

TEST(ExtensionsOf, PerRpc) {
  // Skeletal: BVH, glTF 2.0 (VRM and VRM Animation are glTF files) and FBX.
  EXPECT_THAT(ExtensionsOf("skeletal"),
              ElementsAre(".bvh", ".glb", ".gltf", ".vrm", ".vrma", ".fbx"));
  EXPECT_THAT(ExtensionsOf("curves"), ElementsAre(".motion3.json", ".csv"));
  // LipBlink: curve files and voice recordings.
  EXPECT_THAT(ExtensionsOf("lipblink"), ElementsAre(".motion3.json", ".csv", ".wav", ".flac",
                                                    ".ogg", ".oga", ".opus", ".mp3"));
  // LipBlink with the Spine flags: skeletons only.
  EXPECT_THAT(ExtensionsOf("lipblink", /*spine_skeletons=*/true), ElementsAre(".json"));
  EXPECT_THAT(ExtensionsOf("curves", /*spine_skeletons=*/true), ElementsAre(".json"));
}

}  // namespace
}  // namespace koma::client::batch

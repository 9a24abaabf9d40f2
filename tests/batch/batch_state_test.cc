// The skip manifest (Manifest) and the options fingerprints (BatchCommandLine) that decide
// which clips a rerun of `koma batch` redoes; the batch command line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "client/batch/batch_command.h"
#include "client/batch/batch_state.h"
#include "tests/batch/scratch_folder.h"
#include "tests/testing/status_matchers.h"

namespace koma::client::batch {
namespace {

namespace fs = std::filesystem;
using ::koma::testing::IsOk;

class ManifestTest : public ScratchFolder {
 protected:
  void SetUp() override {
    ScratchFolder::SetUp();
    fs::create_directories(root_ / "in");
    fs::create_directories(root_ / "out");
    item_.input = (root_ / "in/a.bvh").string();
    item_.relative = "a.bvh";
    item_.output = (root_ / "out/a.bvh").string();
    std::ofstream(item_.input) << "in";
    std::ofstream(item_.output) << "out";
    // The output one second after its input, as after a run.
    fs::last_write_time(item_.output, fs::last_write_time(item_.input) + std::chrono::seconds(1));
  }
  std::string Out() const { return (root_ / "out").string(); }

  BatchItem item_;
};

TEST_F(ManifestTest, SavedEntryMakesTheOutputUpToDateAfterReload) {
  Manifest manifest = Manifest::Load(Out());
  EXPECT_FALSE(manifest.UpToDate(item_, "f1"));  // no manifest yet
  manifest.Set(item_, "f1");
  ASSERT_THAT(manifest.Save(), IsOk());
  const Manifest reloaded = Manifest::Load(Out());
  EXPECT_TRUE(reloaded.UpToDate(item_, "f1"));
  EXPECT_FALSE(reloaded.UpToDate(item_, "f2"));  // other options
}

TEST_F(ManifestTest, NewerInputMissingOutputOrOtherInputIsNotUpToDate) {
  Manifest manifest = Manifest::Load(Out());
  manifest.Set(item_, "f1");
  ASSERT_TRUE(manifest.UpToDate(item_, "f1"));
  // Equal times count as up to date (as in make); an input written later does not.
  fs::last_write_time(item_.input, fs::last_write_time(item_.output));
  EXPECT_TRUE(manifest.UpToDate(item_, "f1"));
  fs::last_write_time(item_.input, fs::last_write_time(item_.output) + std::chrono::seconds(1));
  EXPECT_FALSE(manifest.UpToDate(item_, "f1"));
  fs::last_write_time(item_.input, fs::last_write_time(item_.output) - std::chrono::seconds(1));
  BatchItem other = item_;
  other.input = (root_ / "in/../in/./a.bvh").string();  // the same file: same entry
  EXPECT_TRUE(manifest.UpToDate(other, "f1"));
  std::ofstream((root_ / "b.bvh").string()) << "in";
  fs::last_write_time(root_ / "b.bvh", fs::last_write_time(item_.input));
  other.input = (root_ / "b.bvh").string();  // another input of the same name
  EXPECT_FALSE(manifest.UpToDate(other, "f1"));
  BatchItem with_timing = item_;
  with_timing.timing = (root_ / "out/a.timing.csv").string();
  EXPECT_FALSE(manifest.UpToDate(with_timing, "f1"));  // the sheet was never written
  BatchItem with_report = item_;
  with_report.report = (root_ / "out/a.report.html").string();
  EXPECT_FALSE(manifest.UpToDate(with_report, "f1"));  // nor the report
  fs::remove(item_.output);
  EXPECT_FALSE(manifest.UpToDate(item_, "f1"));
}

TEST_F(ManifestTest, ErasedEntryAndUnreadableFileMeanRedo) {
  Manifest manifest = Manifest::Load(Out());
  manifest.Set(item_, "f1");
  manifest.Erase(item_.relative);
  EXPECT_FALSE(manifest.UpToDate(item_, "f1"));
  std::ofstream((root_ / "out" / Manifest::kFileName).string()) << "{not json";
  EXPECT_FALSE(Manifest::Load(Out()).UpToDate(item_, "f1"));
}

// The fingerprint of a batch command line (parsed as `koma batch ...`).
std::string FingerprintOf(std::vector<std::string> args) {
  args.insert(args.begin(), {"koma", "batch"});
  BatchCommandLine line;
  EXPECT_EQ(ParseBatchCommandLine(args, &line), -1);
  return line.fingerprint;
}

TEST(Fingerprint, EqualForEqualOptionsDifferentForAnyChange) {
  const std::string base = FingerprintOf({"skeletal", "in", "-o", "out"});
  // Inputs, output folder, servers, jobs, deadline, progress, timing sheets: not in it.
  EXPECT_EQ(FingerprintOf({"skeletal", "a", "b", "-o", "elsewhere", "--server", "h:1,h:2",
                           "--jobs", "9", "--deadline", "5", "--quiet", "--timing", "--force",
                           "--verbose", "--summary", "s.json", "--progress-every", "1"}),
            base);
  const std::string omit = FingerprintOf({"skeletal", "in", "-o", "out", "--omit", "3"});
  EXPECT_NE(omit, base);
  // Argument order and aliases do not matter; values do.
  EXPECT_EQ(FingerprintOf({"skeletal", "--omissions", "3", "in", "-o", "out"}), omit);
  EXPECT_EQ(FingerprintOf({"skeletal", "in", "--hold", "5", "-o", "out", "--omit", "3"}),
            FingerprintOf({"skeletal", "in", "--omit", "3", "-o", "out", "--holds", "5"}));
  EXPECT_NE(FingerprintOf({"skeletal", "in", "-o", "out", "--omit", "4"}), omit);
  EXPECT_NE(FingerprintOf({"skeletal", "in", "-o", "out", "--timing-fps", "0"}), base);
  EXPECT_NE(FingerprintOf({"skeletal", "in", "-o", "out", "--output-rate", "timing"}), base);
  EXPECT_NE(FingerprintOf({"skeletal", "in", "-o", "out", "--root-relative"}), base);
  // The RPC is part of it; so is a CSV's frame rate (the input reads otherwise).
  const std::string curves = FingerprintOf({"curves", "in", "-o", "out"});
  EXPECT_NE(curves, base);
  EXPECT_NE(FingerprintOf({"lipblink", "in", "-o", "out"}), curves);
  EXPECT_NE(FingerprintOf({"curves", "in", "-o", "out", "--fps", "25"}), curves);
  EXPECT_NE(FingerprintOf({"curves", "in", "-o", "out", "--curve-on", "ParamHair=2"}), curves);
  EXPECT_NE(FingerprintOf({"lipblink", "in", "-o", "out", "--seed", "7"}),
            FingerprintOf({"lipblink", "in", "-o", "out", "--seed", "8"}));
}

TEST(BatchCommandLine, PerFileOptionsAreNotTakenAndUsageErrorsExit2) {
  BatchCommandLine line;
  EXPECT_EQ(ParseBatchCommandLine({"koma", "batch", "skeletal", "a", "b", "-o", "out", "--omit",
                                   "2", "--server", "h:1,h:2", "--jobs", "3", "--timing"},
                                  &line),
            -1);
  EXPECT_EQ(line.rpc, "skeletal");
  EXPECT_THAT(line.args.inputs, ::testing::ElementsAre("a", "b"));
  EXPECT_EQ(line.args.out_dir, "out");
  EXPECT_EQ(line.args.skeletal.omissions, 2);
  EXPECT_EQ(line.args.skeletal.server, "h:1,h:2");
  EXPECT_EQ(line.args.jobs, 3);
  EXPECT_TRUE(line.args.timing);
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {"koma", "batch"},                                                  // no RPC
           {"koma", "batch", "skeletal", "a"},                                 // no -o
           {"koma", "batch", "skeletal", "-o", "out"},                         // no input
           {"koma", "batch", "morph", "a", "-o", "out"},                       // no such RPC
           {"koma", "batch", "skeletal", "a", "-o", "out", "--timing-only"},   // per file
           {"koma", "batch", "curves", "a", "-o", "out", "--omit", "3"},       // another RPC's
           {"koma", "batch", "skeletal", "a", "-o", "out", "--jobs", "0"}}) {  // out of range
    BatchCommandLine ignored;
    EXPECT_EQ(ParseBatchCommandLine(bad, &ignored), 2) << bad.back();
  }
}

}  // namespace
}  // namespace koma::client::batch

// The skip manifest (Manifest) and the options fingerprints (Rpc::Fingerprint) that decide
// which clips a rerun of `koma batch` redoes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "client/batch/batch_rpc.h"
#include "client/batch/batch_state.h"
#include "tests/testing/status_matchers.h"

namespace koma::client::batch {
namespace {

namespace fs = std::filesystem;
using ::koma::testing::IsOk;

class ManifestTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("koma_batch_state_test_" + std::to_string(getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
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
  void TearDown() override { fs::remove_all(root_); }

  std::string Out() const { return (root_ / "out").string(); }

  fs::path root_;
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

TEST(Fingerprint, EqualForEqualOptionsDifferentForAnyChange) {
  SkeletalArgs skeletal;
  const std::string base = MakeSkeletalRpc(skeletal)->Fingerprint();
  EXPECT_EQ(MakeSkeletalRpc(skeletal)->Fingerprint(), base);
  skeletal.input = "elsewhere.bvh";  // paths do not shape the output bytes
  skeletal.server = "10.0.0.1:1";
  EXPECT_EQ(MakeSkeletalRpc(skeletal)->Fingerprint(), base);
  SkeletalArgs changed;
  changed.omissions = 4;  // the server default, but set: another request
  EXPECT_NE(MakeSkeletalRpc(changed)->Fingerprint(), base);
  changed = SkeletalArgs();
  changed.timing_fps = 0;
  EXPECT_NE(MakeSkeletalRpc(changed)->Fingerprint(), base);
  changed = SkeletalArgs();
  changed.output_at_timing_rate = true;
  EXPECT_NE(MakeSkeletalRpc(changed)->Fingerprint(), base);

  CurvesArgs curves;
  const std::string curves_base = MakeCurvesRpc(curves)->Fingerprint();
  EXPECT_NE(curves_base, base);
  CurvesArgs other_fps = curves;
  other_fps.csv_fps = 30.000000001;  // read differently: another output
  EXPECT_NE(MakeCurvesRpc(other_fps)->Fingerprint(), curves_base);
  CurvesArgs override_curve = curves;
  override_curve.curve_on = {"ParamHair=2"};
  EXPECT_NE(MakeCurvesRpc(override_curve)->Fingerprint(), curves_base);

  LipBlinkArgs lip;
  const std::string lip_base = MakeLipBlinkRpc(lip)->Fingerprint();
  EXPECT_NE(lip_base, curves_base);
  lip.seed = 7;
  EXPECT_NE(MakeLipBlinkRpc(lip)->Fingerprint(), lip_base);
}

}  // namespace
}  // namespace koma::client::batch

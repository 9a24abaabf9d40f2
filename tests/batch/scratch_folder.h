// A scratch folder for the batch tests, made fresh for each test and removed after it.
#ifndef KOMA_TESTS_BATCH_SCRATCH_FOLDER_H_
#define KOMA_TESTS_BATCH_SCRATCH_FOLDER_H_

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace koma::client::batch {

class ScratchFolder : public ::testing::Test {
 protected:
  // /tmp/koma_SUITE_PID_TEST: one per test and process, so parallel runs do not meet.
  void SetUp() override {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = std::filesystem::temp_directory_path() /
            ("koma_" + std::string(test->test_suite_name()) + "_" + std::to_string(getpid()) +
             "_" + test->name());
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_);
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  // Writes `text` to root/relative (folders made as needed); its full path.
  std::string Touch(const std::string& relative, const std::string& text = "x") {
    const std::filesystem::path path = root_ / relative;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }
  // The full path of root/relative.
  std::string P(const std::string& relative) const { return (root_ / relative).string(); }

  std::filesystem::path root_;
};

}  // namespace koma::client::batch

#endif  // KOMA_TESTS_BATCH_SCRATCH_FOLDER_H_

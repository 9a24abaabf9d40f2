// WriteFile: whole files only, through symbolic links (the link survives), straight into
// devices and pipes, permissions kept.
#include "client/files.h"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "tests/testing/status_matchers.h"

namespace koma::client {
namespace {

using ::koma::testing::IsOk;
namespace fs = std::filesystem;

class FilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/koma_files_test_XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  static std::string Contents(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // Names in the folder, to prove no temporary file is left behind.
  std::vector<std::string> Names() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  std::string dir_;
};

TEST_F(FilesTest, WritesAndReplacesARegularFile) {
  ASSERT_THAT(WriteFile(Path("a.bvh"), "one"), IsOk());
  ASSERT_THAT(WriteFile(Path("a.bvh"), "two"), IsOk());
  EXPECT_EQ(Contents(Path("a.bvh")), "two");
  EXPECT_THAT(Names(), ::testing::ElementsAre("a.bvh"));
  EXPECT_EQ(*ReadFile(Path("a.bvh")), "two");
}

TEST_F(FilesTest, WritesThroughASymlinkAndKeepsIt) {
  ASSERT_THAT(WriteFile(Path("real.bvh"), "old"), IsOk());
  fs::create_symlink("real.bvh", Path("link.bvh"));
  ASSERT_THAT(WriteFile(Path("link.bvh"), "new"), IsOk());
  EXPECT_TRUE(fs::is_symlink(Path("link.bvh")));
  EXPECT_EQ(fs::read_symlink(Path("link.bvh")), "real.bvh");
  EXPECT_EQ(Contents(Path("real.bvh")), "new");
  EXPECT_THAT(Names(), ::testing::ElementsAre("link.bvh", "real.bvh"));
}

TEST_F(FilesTest, FollowsAChainOfLinksAcrossFolders) {
  fs::create_directory(Path("sub"));
  ASSERT_THAT(WriteFile(Path("sub/real.csv"), "x"), IsOk());
  fs::create_symlink("sub/real.csv", Path("one"));
  fs::create_symlink(Path("one"), Path("two"));  // absolute
  ASSERT_THAT(WriteFile(Path("two"), "chained"), IsOk());
  EXPECT_TRUE(fs::is_symlink(Path("one")));
  EXPECT_TRUE(fs::is_symlink(Path("two")));
  EXPECT_EQ(Contents(Path("sub/real.csv")), "chained");
}

TEST_F(FilesTest, CreatesTheTargetOfADanglingLink) {
  fs::create_symlink("made.bvh", Path("dangling.bvh"));
  ASSERT_THAT(CheckWritable({Path("dangling.bvh")}), IsOk());
  ASSERT_THAT(WriteFile(Path("dangling.bvh"), "made"), IsOk());
  EXPECT_TRUE(fs::is_symlink(Path("dangling.bvh")));
  EXPECT_EQ(Contents(Path("made.bvh")), "made");
}

TEST_F(FilesTest, KeepsPermissionBits) {
  ASSERT_THAT(WriteFile(Path("a.csv"), "1"), IsOk());
  ASSERT_EQ(::chmod(Path("a.csv").c_str(), 0640), 0);
  ASSERT_THAT(WriteFile(Path("a.csv"), "2"), IsOk());
  struct stat info {};
  ASSERT_EQ(::stat(Path("a.csv").c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0640u);
}

TEST_F(FilesTest, NewFileGetsTheUsualMode) {
  const mode_t old_mask = ::umask(022);
  ASSERT_THAT(WriteFile(Path("n.csv"), "1"), IsOk());
  ::umask(old_mask);
  struct stat info {};
  ASSERT_EQ(::stat(Path("n.csv").c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0644u);
}

TEST_F(FilesTest, WritesIntoADeviceWithoutReplacingIt) {
  ASSERT_THAT(CheckWritable({"/dev/null"}), IsOk());
  ASSERT_THAT(WriteFile("/dev/null", "discarded"), IsOk());
  struct stat info {};
  ASSERT_EQ(::stat("/dev/null", &info), 0);
  EXPECT_TRUE(S_ISCHR(info.st_mode));
  // And through a link to it.
  fs::create_symlink("/dev/null", Path("null"));
  ASSERT_THAT(WriteFile(Path("null"), "discarded"), IsOk());
  EXPECT_TRUE(fs::is_symlink(Path("null")));
}

TEST_F(FilesTest, WritesIntoANamedPipe) {
  ASSERT_EQ(::mkfifo(Path("pipe").c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = Contents(Path("pipe")); });
  EXPECT_THAT(WriteFile(Path("pipe"), "through the pipe"), IsOk());
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  struct stat info {};
  ASSERT_EQ(::lstat(Path("pipe").c_str(), &info), 0);
  EXPECT_TRUE(S_ISFIFO(info.st_mode));
}

TEST_F(FilesTest, ErrorsNameThePath) {
  EXPECT_THAT(
      WriteFile(Path("missing/x.bvh"), "x"),
      koma::testing::StatusIs(absl::StatusCode::kNotFound,
                              ::testing::StartsWith("cannot write " + Path("missing/x.bvh"))));
  EXPECT_THAT(
      CheckWritable({Path("missing/x.bvh")}),
      koma::testing::StatusIs(absl::StatusCode::kNotFound,
                              ::testing::StartsWith("cannot write " + Path("missing/x.bvh"))));
  EXPECT_THAT(CheckWritable({dir_}),
              koma::testing::StatusIs(absl::StatusCode::kFailedPrecondition,
                                      ::testing::HasSubstr("Is a directory")));
  EXPECT_THAT(ReadFile(Path("none.bvh")),
              koma::testing::StatusIs(absl::StatusCode::kNotFound,
                                      ::testing::Eq("cannot read " + Path("none.bvh") +
                                                    ": No such file or directory")));
  EXPECT_THAT(ReadFile(dir_), koma::testing::StatusIs(absl::StatusCode::kFailedPrecondition,
                                                      ::testing::HasSubstr("Is a directory")));
  fs::create_symlink("loop2", Path("loop1"));
  fs::create_symlink("loop1", Path("loop2"));
  EXPECT_FALSE(WriteFile(Path("loop1"), "x").ok());
  EXPECT_TRUE(fs::is_symlink(Path("loop1")));
}

TEST_F(FilesTest, StdioNames) {
  EXPECT_TRUE(IsStdio("-"));
  EXPECT_FALSE(IsStdio("./-"));
  EXPECT_THAT(CheckWritable({"-"}), IsOk());
}

}  // namespace
}  // namespace koma::client

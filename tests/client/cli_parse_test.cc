// The command line parser on its own (no server): koma's checks before CLI11's, presets and
// the --config file with their precedence, and the exit code and first message line of misuse.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "client/cli.h"

namespace koma::client {
namespace {

const std::string kBvh = std::string(KOMA_SAMPLES_DIR) + "/pitch.bvh";

struct Parsed {
  int code = 0;
  std::string first_error_line;
  KomaCommandLine line;
};

Parsed Parse(std::vector<std::string> args) {
  args.insert(args.begin(), "koma");
  Parsed parsed;
  ::testing::internal::CaptureStderr();
  parsed.code = ParseCommandLine(args, &parsed.line);
  const std::string err = ::testing::internal::GetCapturedStderr();
  parsed.first_error_line = err.substr(0, err.find('\n'));
  return parsed;
}

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CliParseTest, RunsACommand) {
  const Parsed p = Parse({"skeletal", kBvh, "-o", "out.bvh", "--omit", "5", "--json"});
  EXPECT_EQ(p.code, -1);
  EXPECT_EQ(p.line.command, "skeletal");
  EXPECT_EQ(p.line.skeletal.omissions, 5);
  EXPECT_TRUE(p.line.skeletal.json);
  EXPECT_EQ(p.first_error_line, "");
}

TEST(CliParseTest, MisuseExitCodesAndFirstLines) {
  struct Case {
    std::vector<std::string> args;
    std::string first_line;
  };
  const std::vector<Case> cases = {
      {{}, "koma: a command is required: skeletal, curves, lipblink, live, health, batch"},
      {{"curvs"}, "koma: unknown command \"curvs\"; did you mean \"curves\"?"},
      {{"skeletal", kBvh, "--max-hld", "2"},
       "koma skeletal: unknown option --max-hld; did you mean --max-hold?"},
      {{"skeletal", kBvh, "-o", "--timing", "t.csv"},
       "koma skeletal: -o needs a value (--timing is an option)"},
      {{"skeletal", kBvh, "-o", "o.bvh", "--hold", "x"},
       "koma skeletal: --hold: \"x\" is not a whole number"},
      {{"lipblink", kBvh, "-o", "o.json", "--auto-blink-hold", "4"},
       "koma lipblink: --auto-blink-hold: 4 is too large: the largest allowed is 3"},
      {{"lipblink", kBvh, "-o", "o.json", "--eyes-threshold", "0.5"},
       "koma lipblink: --eyes-threshold: 0.5 is out of range: must be between 0 and 0.5 (both "
       "excluded)"},
      {{"lipblink", kBvh, "-o", "o.json", "--eyes-linked", "maybe"},
       "koma lipblink: --eyes-linked: \"maybe\" is not true or false"},
      {{"curves", kBvh, "-o", "o.json", "--fps", "-30"},
       "koma curves: --fps: -30 is out of range: must be greater than 0"},
      {{"curves", kBvh, "-o", "o.json", "--keys", "0,-5"},
       "koma curves: --keys: -5 is too small: the smallest allowed is 0"},
      {{"curves", kBvh, "-o", "o.json", "--format", "xml"},
       "koma curves: --format: \"xml\" is not one of motion3, csv"},
      {{"--json", "health"},
       "koma: --json is an option of `koma health`: put it after the command (koma health ... "
       "--json)"},
  };
  for (const Case& c : cases) {
    const Parsed p = Parse(c.args);
    EXPECT_EQ(p.code, 2) << c.first_line;
    EXPECT_EQ(p.first_error_line, c.first_line);
  }
}

TEST(CliParseTest, VersionAndHelpExitZero) {
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(Parse({"--version"}).code, 0);
  EXPECT_THAT(::testing::internal::GetCapturedStdout(), ::testing::StartsWith("koma 0."));
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(Parse({"curves", "--help"}).code, 0);
  EXPECT_THAT(::testing::internal::GetCapturedStdout(),
              ::testing::HasSubstr("--segment-overrides"));
}

TEST(CliParseTest, PresetsAreFlagsThatLaterFlagsOverride) {
  Parsed p = Parse({"skeletal", kBvh, "-o", "o.bvh", "--preset", "snappy"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, std::nullopt);
  EXPECT_EQ(p.line.skeletal.omissions_per_second, 1.5);
  EXPECT_EQ(p.line.skeletal.drawings_per_second, 8.0);
  EXPECT_EQ(p.line.skeletal.max_hold, std::nullopt);  // the server's: the hold the rate needs
  p = Parse({"skeletal", kBvh, "--omit", "1", "-o", "o.bvh", "--preset=snappy"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, 1);  // given on the line: wins wherever it stands
  EXPECT_EQ(p.line.skeletal.omissions_per_second, std::nullopt);  // and replaces the preset's rate
  EXPECT_EQ(p.line.skeletal.drawings_per_second, 8.0);
  p = Parse({"skeletal", kBvh, "-o", "o.bvh", "--preset", "threes", "--drawings-per-second", "6"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.drawings_per_second, 6.0);
  p = Parse({"skeletal", kBvh, "-o", "o.bvh", "--preset", "twos"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.drawings_per_second, 12.0);
  p = Parse({"curves", kBvh, "-o", "o.json", "--preset", "snappy"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.curves.frames_per_drawing, 3);
  EXPECT_EQ(p.line.curves.tame, 1.5);
  EXPECT_EQ(p.line.curves.tsume, 2.0);
  p = Parse({"lipblink", kBvh, "-o", "o.json", "--preset", "subtle"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.lip_blink.frames_per_shape, 3);
  EXPECT_EQ(p.line.lip_blink.mode, "follow");
}

TEST(CliParseTest, ConfigFileLosesToPresetAndFlags) {
  const std::string config =
      WriteTemp("koma.toml",
                "[skeletal]\nomissions = 5\nmax-hold = 1\nserver = \"farm:1\"\n"
                "[curves]\ntame = 2.5\n");
  Parsed p = Parse({"--config", config, "skeletal", kBvh, "-o", "o.bvh"});
  ASSERT_EQ(p.code, -1) << p.first_error_line;
  EXPECT_EQ(p.line.skeletal.omissions, 5);
  EXPECT_EQ(p.line.skeletal.max_hold, 1);
  EXPECT_EQ(p.line.skeletal.server, "farm:1");
  p = Parse({"--config", config, "skeletal", kBvh, "-o", "o.bvh", "--preset", "twos"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, 5);
  EXPECT_EQ(p.line.skeletal.drawings_per_second, 12.0);
  EXPECT_EQ(p.line.skeletal.max_hold, 1);  // the preset sets no max-hold: the config's stays
  // The preset's omission rate wins over the config's count (not both: the server refuses
  // that); a count on the line wins over both.
  p = Parse({"--config", config, "skeletal", kBvh, "-o", "o.bvh", "--preset", "snappy"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, std::nullopt);
  EXPECT_EQ(p.line.skeletal.omissions_per_second, 1.5);
  p = Parse({"--config", config, "skeletal", kBvh, "-o", "o.bvh", "--preset", "snappy", "--omit",
             "2"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, 2);
  EXPECT_EQ(p.line.skeletal.omissions_per_second, std::nullopt);
  p = Parse({"--config", config, "skeletal", kBvh, "-o", "o.bvh", "--max-hold", "3", "--server",
             "here:2"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.max_hold, 3);
  EXPECT_EQ(p.line.skeletal.server, "here:2");
  p = Parse({"--config", config, "curves", kBvh, "-o", "o.json"});
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.curves.tame, 2.5);
  // From the environment.
  ::setenv("KOMA_CONFIG", config.c_str(), 1);
  p = Parse({"skeletal", kBvh, "-o", "o.bvh"});
  ::unsetenv("KOMA_CONFIG");
  ASSERT_EQ(p.code, -1);
  EXPECT_EQ(p.line.skeletal.omissions, 5);
}

TEST(CliParseTest, ConfigFileMistakesAreNamed) {
  const std::string typo = WriteTemp("typo.toml", "[curves]\ntsune = 2\n");
  Parsed p = Parse({"--config", typo, "curves", kBvh, "-o", "o.json"});
  EXPECT_EQ(p.code, 2);
  EXPECT_EQ(p.first_error_line,
            "koma: --config " + typo + ": [curves] tsune: unknown option; did you mean tsume?");
  const std::string bad_value = WriteTemp("bad.toml", "[skeletal]\nomissions = -1\n");
  p = Parse({"--config", bad_value, "skeletal", kBvh, "-o", "o.bvh"});
  EXPECT_EQ(p.code, 2);
  EXPECT_EQ(p.first_error_line,
            "koma skeletal: --omit: -1 is too small: the smallest allowed is 0");
}

}  // namespace
}  // namespace koma::client

// `koma batch lipblink --audio-beside`: which recording goes with which input, the errors when
// none or several match, what happens to the recordings among the inputs, and the manifest
// redoing an item when its recording changes.
#include "client/batch/batch_audio_beside.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "client/batch/batch_command.h"
#include "client/batch/batch_inputs.h"
#include "client/batch/batch_state.h"
#include "tests/batch/scratch_folder.h"
#include "tests/testing/status_matchers.h"

namespace koma::client::batch {
namespace {

namespace fs = std::filesystem;
using ::koma::testing::IsOk;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

class AudioBeside : public ScratchFolder {
 protected:
  // The items of a lipblink batch over `inputs` with --audio-beside.
  std::vector<BatchItem> Discover(const std::vector<std::string>& inputs) {
    absl::StatusOr<std::vector<BatchItem>> items =
        DiscoverInputs(inputs, ExtensionsOf("lipblink"), P("out"), false, /*with_report=*/true,
                       false, /*audio_beside=*/true);
    EXPECT_THAT(items.status(), IsOk());
    return items.ok() ? *items : std::vector<BatchItem>{};
  }
};

TEST_F(AudioBeside, StemDropsTheInputEnding) {
  EXPECT_EQ(RecordingStem("hero.json"), "hero");
  EXPECT_EQ(RecordingStem("hero.JSON"), "hero");
  EXPECT_EQ(RecordingStem("walk.motion3.json"), "walk");
  EXPECT_EQ(RecordingStem("walk.Motion3.Json"), "walk");
  EXPECT_EQ(RecordingStem("arm.csv"), "arm");
  EXPECT_EQ(RecordingStem("take.v2.bvh"), "take.v2");
  EXPECT_EQ(RecordingStem("a.b.json"), "a.b");
}

TEST_F(AudioBeside, EachInputTakesTheRecordingOfItsNameInItsFolder) {
  const std::string hero = Touch("skel/hero.json");
  Touch("skel/hero.WAV");           // any case of the extension
  Touch("skel/hero_old.wav");       // another name
  Touch("skel/hero.json.wav");      // another name
  Touch("other/villain.flac");      // another folder
  const std::string villain = Touch("skel/villain.json");
  Touch("skel/villain.flac");
  const std::string walk = Touch("motions/walk.motion3.json");
  Touch("motions/walk.mp3");
  Touch("motions/walk.motion3.wav");  // the stem of walk.motion3.json is "walk"
  const std::vector<BatchItem> items = Discover({hero, villain, walk});
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].audio, P("skel/hero.WAV"));
  EXPECT_EQ(items[1].audio, P("skel/villain.flac"));
  EXPECT_EQ(items[2].audio, P("motions/walk.mp3"));
  for (const BatchItem& item : items) EXPECT_EQ(item.audio_error, "") << item.input;
  // The outputs are the inputs' own (the recording writes nothing).
  EXPECT_EQ(items[0].output, P("out/hero.json"));
  EXPECT_EQ(items[0].report, P("out/hero.json.report.html"));  // not a skeleton extension here
}

TEST_F(AudioBeside, RelativeInputGivesARelativeRecording) {
  Touch("hero.json");
  Touch("hero.ogg");
  const fs::path before = fs::current_path();
  fs::current_path(root_);
  const std::vector<std::string> found = RecordingsBeside("hero.json");
  fs::current_path(before);
  EXPECT_THAT(found, ElementsAre("hero.ogg"));
}

TEST_F(AudioBeside, NoneOrSeveralRecordingsFailThatItemNamingTheCandidates) {
  const std::string alone = Touch("skel/alone.json");
  const std::string twice = Touch("skel/twice.json");
  Touch("skel/twice.wav");
  Touch("skel/twice.flac");
  const std::string fine = Touch("skel/fine.json");
  Touch("skel/fine.opus");
  const std::vector<BatchItem> items = Discover({alone, twice, fine});
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].audio, "");
  EXPECT_EQ(items[0].audio_error,
            "--audio-beside: no recording beside " + alone +
                " (looked for alone.wav, alone.flac, alone.ogg, alone.oga, alone.opus, alone.mp3)");
  EXPECT_EQ(items[1].audio, "");
  EXPECT_EQ(items[1].audio_error, "--audio-beside: 2 recordings beside " + twice + ": " +
                                      P("skel/twice.flac") + ", " + P("skel/twice.wav") +
                                      " (keep one of them there)");
  EXPECT_EQ(items[2].audio, P("skel/fine.opus"));
  EXPECT_EQ(items[2].audio_error, "");
}

TEST_F(AudioBeside, PairedRecordingsAmongTheInputsAreNotItemsOfTheirOwn) {
  // A folder of motions with their voices, and a stray recording: the paired recordings go
  // with their motions (no second NAME.motion3.json from them, which would also collide with
  // the motion's own output); the stray one fails, named.
  Touch("in/a.motion3.json");
  Touch("in/a.wav");
  Touch("in/sub/b.csv");
  Touch("in/sub/b.flac");
  Touch("in/stray.mp3");
  const std::vector<BatchItem> items = Discover({P("in")});
  std::map<std::string, BatchItem> by_relative;
  for (const BatchItem& item : items) by_relative[item.relative] = item;
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(by_relative["a.motion3.json"].audio, P("in/a.wav"));
  EXPECT_EQ(by_relative["sub/b.csv"].audio, P("in/sub/b.flac"));
  EXPECT_EQ(by_relative["stray.mp3"].audio, "");
  EXPECT_THAT(by_relative["stray.mp3"].audio_error,
              HasSubstr(P("in/stray.mp3") + " is a recording with no input of its name beside it"));
  // A skeleton beside a recording that is not an input (folders collect *.json only with the
  // Spine flags): the message says so.
  Touch("skel/hero.json");
  Touch("skel/hero.wav");
  const std::vector<BatchItem> skel = Discover({P("skel")});
  ASSERT_EQ(skel.size(), 1u);
  EXPECT_THAT(skel[0].audio_error,
              HasSubstr("; " + P("skel/hero.json") + " is beside it but not an input (name it, "
                        "or give the Spine flags so that folders collect *.json)"));
  // Named twice (the folder and the file): still taken once, with its motion.
  const std::vector<BatchItem> again = Discover({P("in/a.wav"), P("in/a.motion3.json")});
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].relative, "a.motion3.json");
  EXPECT_EQ(again[0].audio, P("in/a.wav"));
}

TEST_F(AudioBeside, AFolderOfSkeletonsWithTheSpineFlagsPairsEach) {
  // lipblink with the Spine flags collects *.json from folders (ExtensionsOf(.., true)); the
  // recordings beside are found on disk, not collected.
  Touch("skel/hero.json");
  Touch("skel/hero.wav");
  Touch("skel/sub/villain.json");
  Touch("skel/sub/villain.mp3");
  ASSERT_OK_AND_ASSIGN(
      std::vector<BatchItem> items,
      DiscoverInputs({P("skel")}, ExtensionsOf("lipblink", /*spine_skeletons=*/true), P("out"),
                     false, /*with_report=*/true, false, /*audio_beside=*/true));
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].relative, "hero.json");
  EXPECT_EQ(items[0].audio, P("skel/hero.wav"));
  EXPECT_EQ(items[0].report, P("out/hero.report.html"));
  EXPECT_EQ(items[1].relative, "sub/villain.json");
  EXPECT_EQ(items[1].audio, P("skel/sub/villain.mp3"));
}

TEST_F(AudioBeside, WithoutTheFlagRecordingsStayInputsOfTheirOwn) {
  Touch("in/a.motion3.json");
  Touch("in/b.wav");
  ASSERT_OK_AND_ASSIGN(std::vector<BatchItem> items,
                       DiscoverInputs({P("in")}, ExtensionsOf("lipblink"), P("out"), false));
  ASSERT_EQ(items.size(), 2u);
  for (const BatchItem& item : items) {
    EXPECT_EQ(item.audio, "");
    EXPECT_EQ(item.audio_error, "");
  }
  EXPECT_EQ(items[1].output, P("out/b.motion3.json"));
}

// Random trees against a naive reference written from the documented rule: an input (not a
// recording) takes the one file in its folder named its stem + an audio extension (any case);
// taken recordings leave the items; the others stay, in order.
TEST_F(AudioBeside, RandomTreesMatchANaiveReference) {
  std::mt19937 rng(20261127);
  const std::vector<std::string> stems = {"a", "b", "A", "a.b"};
  const std::vector<std::string> endings = {".json", ".motion3.json", ".csv", ".txt",
                                            ".json.wav"};
  const std::vector<std::string> recordings = {".wav", ".FLAC", ".mp3", ".Opus", ".ogg"};
  const std::vector<std::string> audio = {".wav", ".flac", ".ogg", ".oga", ".opus", ".mp3"};
  int compared = 0;
  for (int round = 0; round < 120; ++round) {
    fs::remove_all(root_);
    std::vector<std::string> files;  // relative to root_
    for (const std::string folder : {"x", "x/y"}) {
      for (const std::string& stem : stems) {
        for (const std::string& ending : endings) {
          if (rng() % 3 == 0) files.push_back(Touch(folder + "/" + stem + ending));
        }
        // Recordings: none, one or (less often) two of the stem, in random extensions.
        const int count = std::vector<int>{0, 0, 1, 1, 1, 2}[rng() % 6];
        for (int k = 0; k < count; ++k) {
          files.push_back(Touch(folder + "/" + stem + recordings[rng() % recordings.size()]));
        }
      }
    }
    std::sort(files.begin(), files.end());  // a recording drawn twice is one file
    files.erase(std::unique(files.begin(), files.end()), files.end());
    if (files.empty()) continue;
    // Inputs: the folder, or some files by name.
    std::vector<std::string> inputs;
    if (rng() % 2 == 0) {
      inputs.push_back(P("x"));
    } else {
      for (const std::string& file : files) {
        if (rng() % 2 == 0) inputs.push_back(file);
      }
    }
    if (inputs.empty()) continue;
    absl::StatusOr<std::vector<BatchItem>> with =
        DiscoverInputs(inputs, ExtensionsOf("lipblink"), P("out"), false, false, false, true);
    auto lower = [](std::string text) {
      for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return text;
    };
    auto is_audio = [&](const std::string& name) {
      for (const std::string& ext : audio) {
        if (lower(name).size() > ext.size() &&
            lower(name).substr(lower(name).size() - ext.size()) == ext) {
          return true;
        }
      }
      return false;
    };
    // The inputs as collected (documented: a folder's files by extension in path order, named
    // files as given).
    std::vector<std::string> raw;
    if (inputs.size() == 1 && inputs[0] == P("x")) {
      std::vector<std::pair<std::string, std::string>> found;  // relative, path
      for (const std::string& file : files) {
        const std::string name = fs::path(file).filename().string();
        if (is_audio(name) || absl::EndsWithIgnoreCase(name, ".motion3.json") ||
            absl::EndsWithIgnoreCase(name, ".csv")) {
          found.emplace_back(fs::path(file).lexically_relative(P("x")).string(), file);
        }
      }
      std::sort(found.begin(), found.end());
      for (const auto& [relative, path] : found) raw.push_back(path);
    } else {
      raw = inputs;
    }
    // A clip whose output another would write makes the batch refuse (not this test's case).
    if (!with.ok()) {
      EXPECT_THAT(with.status().message(), HasSubstr("would both write")) << "round " << round;
      continue;
    }
    // The reference.
    std::vector<std::string> expected;        // the inputs left, in order
    std::map<std::string, std::string> pairs;  // input -> its one recording
    std::set<std::string> taken;
    for (const std::string& input : raw) {
      const fs::path path(input);
      if (is_audio(path.filename().string())) continue;
      std::string name = path.filename().string(), stem = name;
      for (const std::string ending : {".motion3.json", ".json", ".csv"}) {
        if (lower(name).size() > ending.size() &&
            lower(name).substr(name.size() - ending.size()) == ending) {
          stem = name.substr(0, name.size() - ending.size());
          break;
        }
      }
      if (stem == name) stem = path.stem().string();
      std::vector<std::string> found;
      for (const std::string& file : files) {
        const fs::path f(file);
        if (f.parent_path() != path.parent_path()) continue;
        const std::string fname = f.filename().string();
        for (const std::string& ext : audio) {
          if (fname.size() == stem.size() + ext.size() && fname.substr(0, stem.size()) == stem &&
              lower(fname.substr(stem.size())) == ext) {
            found.push_back(file);
          }
        }
      }
      if (found.size() == 1) {
        taken.insert(found[0]);
        pairs[input] = found[0];
      }
    }
    for (const std::string& input : raw) {
      if (taken.count(input) == 0) expected.push_back(input);
    }
    ++compared;
    ASSERT_EQ(with->size(), expected.size()) << "round " << round;
    for (size_t i = 0; i < expected.size(); ++i) {
      const BatchItem& got = (*with)[i];
      EXPECT_EQ(got.input, expected[i]) << "round " << round;
      // Its recording, or an error when it has none (or is a recording no input took).
      const auto pair = pairs.find(got.input);
      EXPECT_EQ(got.audio, pair == pairs.end() ? "" : pair->second) << got.input;
      EXPECT_NE(got.audio.empty(), got.audio_error.empty()) << got.input;
    }
  }
  EXPECT_GE(compared, 30) << "rounds compared";  // the others have colliding outputs
}

TEST_F(AudioBeside, ManifestRedoesAnItemWhoseRecordingChangedOrMoved) {
  BatchItem item;
  item.input = Touch("in/hero.json");
  item.audio = Touch("in/hero.wav");
  item.relative = "hero.json";
  item.output = Touch("out/hero.json");
  const auto input_time = fs::last_write_time(item.input);
  fs::last_write_time(item.audio, input_time);
  fs::last_write_time(item.output, input_time + std::chrono::seconds(1));
  Manifest manifest = Manifest::Load(P("out"));
  manifest.Set(item, "f");
  ASSERT_THAT(manifest.Save(), IsOk());
  const Manifest reloaded = Manifest::Load(P("out"));
  EXPECT_TRUE(reloaded.UpToDate(item, "f"));
  // A newer recording: redone, though the skeleton did not change.
  fs::last_write_time(item.audio, input_time + std::chrono::seconds(2));
  EXPECT_FALSE(reloaded.UpToDate(item, "f"));
  fs::last_write_time(item.audio, input_time);
  // Another recording (hero.wav replaced by hero.flac), or none: redone.
  BatchItem moved = item;
  moved.audio = Touch("in/hero.flac");
  fs::last_write_time(moved.audio, input_time);
  EXPECT_FALSE(reloaded.UpToDate(moved, "f"));
  BatchItem without = item;
  without.audio.clear();
  EXPECT_FALSE(reloaded.UpToDate(without, "f"));
}

TEST(AudioBesideFlag, LipblinkOnlyAndInTheFingerprint) {
  BatchCommandLine line;
  ASSERT_EQ(ParseBatchCommandLine({"koma", "batch", "lipblink", "a.json", "-o", "out",
                                   "--audio-beside"},
                                  &line),
            -1);
  EXPECT_TRUE(line.args.audio_beside);
  BatchCommandLine without;
  ASSERT_EQ(ParseBatchCommandLine({"koma", "batch", "lipblink", "a.json", "-o", "out"}, &without),
            -1);
  EXPECT_FALSE(without.args.audio_beside);
  EXPECT_NE(line.fingerprint, without.fingerprint);  // outputs made without it are redone
  BatchCommandLine ignored;
  EXPECT_EQ(ParseBatchCommandLine({"koma", "batch", "curves", "a", "-o", "out", "--audio-beside"},
                                  &ignored),
            2);
}

}  // namespace
}  // namespace koma::client::batch

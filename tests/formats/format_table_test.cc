// The format table (formats/format_table.h): its rows consistent with each other, and its
// sniffing right on every file koma ships or tests with.
#include "formats/format_table.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "formats/spine.h"
#include "tests/formats/test_files.h"

namespace koma::formats {
namespace {

namespace fs = std::filesystem;

TEST(FormatTableTest, KeysAndExtensionsBelongToOneRowEach) {
  std::set<std::string_view> keys;
  std::map<std::string_view, std::string_view> owner;
  for (const FormatRow& row : FormatTable()) {
    EXPECT_NE(row.id, FormatId::kUnknown);
    EXPECT_TRUE(keys.insert(row.key).second) << row.key;
    EXPECT_EQ(&FormatOf(row.id), &row) << row.key;
    EXPECT_EQ(FormatByKey(row.key), &row) << row.key;
    for (std::string_view extension : row.extensions) {
      EXPECT_TRUE(owner.emplace(extension, row.key).second)
          << extension << " is claimed by " << owner[extension] << " and " << row.key;
      // Any case, after any stem, maps back to the row.
      std::string upper = "Some/Take" + std::string(extension);
      for (char& c : upper) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
      EXPECT_EQ(FormatFromName("walk" + std::string(extension)), row.id) << extension;
      EXPECT_EQ(FormatFromName(upper), row.id) << upper;
    }
    // Every folder extension is one of the row's names (or, for a format with no name of its
    // own, the JSON every such file is).
    for (std::string_view folder : row.folder_extensions) {
      const FormatId named = FormatFromName(folder);
      EXPECT_TRUE(named == row.id || (row.extensions.empty() && folder == ".json"))
          << row.key << ": " << folder;
    }
    EXPECT_FALSE(row.reader.empty()) << row.key;
    EXPECT_FALSE(row.inputs.empty()) << row.key << ": no command reads it";
    EXPECT_FALSE(row.request_fields.empty()) << row.key << ": no request carries it";
    EXPECT_GT(row.parse_bytes_per_byte, 0) << row.key;
    EXPECT_GT(row.kept_bytes_per_byte, 0) << row.key;
    for (const CommandInput& input : row.inputs) {
      bool known = false;
      for (const CommandRow& command : CommandTable()) known |= command.name == input.command;
      EXPECT_TRUE(known) << row.key << ": " << input.command;
    }
  }
  EXPECT_EQ(FormatFromName("-"), FormatId::kUnknown);
  EXPECT_EQ(FormatFromName("notes.txt"), FormatId::kUnknown);
  EXPECT_EQ(FormatOf(FormatId::kUnknown).name, "unknown");
}

TEST(FormatTableTest, RequestFieldsMapBack) {
  for (const FormatRow& row : FormatTable()) {
    for (const RequestField& field : row.request_fields) {
      EXPECT_EQ(FormatOfRequestField(field.message, field.field), &row)
          << field.message << "." << field.field;
    }
  }
  EXPECT_EQ(FormatOfRequestField("RetimeSkeletalRequest", "motion"), nullptr);
}

// What a file koma ships or tests with is by its contents: its name's row, except that a
// .json may be a Spine skeleton (told by formats::IsSpineJson, which the table's Spine rule
// must agree with) and that recordings are not sniffed (libsndfile tells them apart).
FormatId ExpectedSniff(const fs::path& path, const std::string& bytes) {
  const FormatId named = FormatFromName(path.string());
  if (named == FormatId::kMotion3 && IsSpineJson(bytes)) return FormatId::kSpine;
  if (named == FormatId::kAudio) return FormatId::kUnknown;
  return named;
}

TEST(FormatTableTest, SniffsEverySampleAndTestFile) {
  int files = 0;
  std::set<FormatId> seen;
  for (const char* folder : {KOMA_SAMPLES_DIR, KOMA_TESTDATA_DIR}) {
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder)) {
      if (!entry.is_regular_file()) continue;
      const FormatId named = FormatFromName(entry.path().string());
      if (named == FormatId::kUnknown) continue;  // scripts, licences, READMEs
      const std::string bytes = ReadTestFile(entry.path().string());
      const FormatId expected = ExpectedSniff(entry.path(), bytes);
      EXPECT_EQ(SniffFormat(bytes), expected) << entry.path();
      if (expected != FormatId::kUnknown) {
        EXPECT_TRUE(MatchesSniff(FormatOf(expected), bytes)) << entry.path();
      }
      seen.insert(expected);
      ++files;
    }
  }
  EXPECT_GE(files, 20);
  // Each sniffed row met at least one real file.
  for (FormatId id : {FormatId::kBvh, FormatId::kGltf, FormatId::kFbx, FormatId::kSpine,
                      FormatId::kMotion3, FormatId::kCsv}) {
    EXPECT_EQ(seen.count(id), 1u) << FormatOf(id).key;
  }
}

TEST(FormatTableTest, SniffsByMagicTextAndJson) {
  EXPECT_EQ(SniffFormat("glTF\x02\0\0\0"), FormatId::kGltf);
  EXPECT_EQ(SniffFormat("Kaydara FBX Binary  \0"), FormatId::kFbx);
  EXPECT_EQ(SniffFormat("; FBX 7.4.0 project file"), FormatId::kFbx);
  EXPECT_EQ(SniffFormat("\xEF\xBB\xBF \r\n\tHIERARCHY"), FormatId::kBvh);
  EXPECT_EQ(SniffFormat("\"frame\";\"a\"\n"), FormatId::kCsv);
  EXPECT_EQ(SniffFormat("{\"asset\":{}}"), FormatId::kGltf);
  EXPECT_EQ(SniffFormat("{\"asset\":{},\"Curves\":[]}"), FormatId::kMotion3);
  EXPECT_EQ(SniffFormat("{ \"skeleton\": {}, \"Meta\": {}}"), FormatId::kSpine);
  EXPECT_EQ(SniffFormat("{\"bones\":[],\"skeleton\":{}}"), FormatId::kSpine);
  EXPECT_EQ(SniffFormat("{\"Meta\":{},\"skeleton\":1}"), FormatId::kMotion3);
  EXPECT_EQ(SniffFormat("{}"), FormatId::kMotion3);
  // A magic counts at the very start only: white space first is not a GLB.
  EXPECT_EQ(SniffFormat(" glTF"), FormatId::kUnknown);
  EXPECT_EQ(SniffFormat("RIFF....WAVE"), FormatId::kUnknown);  // audio: libsndfile's to tell
  // The Spine rule agrees with formats::IsSpineJson on texts it was written for.
  for (const char* text : {"{\"skeleton\":{}}", " \xEF\xBB\xBF{}", "{\"a\":1,\"skeleton\":2}",
                           "{\"Meta\":1,\"skeleton\":2}", "[\"skeleton\"]"}) {
    EXPECT_EQ(MatchesSniff(FormatOf(FormatId::kSpine), text), IsSpineJson(text)) << text;
  }
}

TEST(FormatTableTest, CommandsReadAndWriteTheirFormats) {
  EXPECT_TRUE(TakesInput(FormatOf(FormatId::kBvh), "skeletal"));
  EXPECT_FALSE(TakesInput(FormatOf(FormatId::kBvh), "curves"));
  EXPECT_TRUE(TakesInput(FormatOf(FormatId::kAudio), "lipblink", "--audio"));
  EXPECT_FALSE(TakesInput(FormatOf(FormatId::kAudio), "lipblink"));
  EXPECT_TRUE(WrittenBy(FormatOf(FormatId::kFbx), "skeletal"));
  EXPECT_FALSE(WrittenBy(FormatOf(FormatId::kAudio), "lipblink"));
  // The formats the server reads and answers whole are exactly the skeletal ones it writes
  // back in kind, not BVH (which the client decodes unless --send-file).
  for (const FormatRow& row : FormatTable()) {
    if (row.sent_whole) {
      EXPECT_TRUE(TakesInput(row, "skeletal") && WrittenBy(row, "skeletal")) << row.key;
    }
  }
}

}  // namespace
}  // namespace koma::formats

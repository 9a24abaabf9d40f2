// ParseJsonText (nlohmann's SAX events built into an ordered_json, members collected before an
// object's vector is made) against ParseJsonTextByDom (nlohmann's own Json::parse): the same
// document, node for node and type for type (integer, unsigned, float), the same key order and
// the same handling of a key given twice (first position, last value), in objects small and
// large (the builder looks keys up linearly up to 16 members, in a hash table beyond), and the
// same error message for malformed text, on 3,000 random texts and their broken variants.
#include <gtest/gtest.h>

#include <string>

#include "absl/strings/str_cat.h"
#include "core/split_mix64.h"
#include "core/stop_check.h"
#include "formats/json_text.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using Json = nlohmann::ordered_json;

std::string RandomKey(SplitMix64& rng, int members) {
  // Few distinct keys in big objects, so that keys repeat.
  static const char* const kKeys[] = {"a", "b", "time", "x", "\\u00e9", "\xC3\xA9", "a\\\"b", ""};
  if (rng.OneIn(3)) return kKeys[rng.Int(0, 7)];
  return absl::StrCat("k", rng.Int(0, members + 3));
}

std::string RandomJson(SplitMix64& rng, int depth) {
  switch (rng.Int(0, depth > 0 ? 9 : 5)) {
    case 0:
      return absl::StrCat(rng.Int(-100000, 100000));
    case 1:
      return absl::StrCat(200 * rng.Unit() - 100);
    case 2: {
      static const char* const kNumbers[] = {"18446744073709551615",
                                             "-9223372036854775808",
                                             "9223372036854775808",
                                             "1e5",
                                             "-0",
                                             "0.0",
                                             "1.5E-3",
                                             "123456789012345678901234567890",
                                             "18446744073709551616",
                                             "-9223372036854775809",
                                             "-0.0",
                                             "1E+2",
                                             "1e-400",
                                             "4.9e-324",
                                             "2.2250738585072011e-308",
                                             "0.1",
                                             "-1.25e10",
                                             "1.7976931348623157e308",
                                             "0.30000000000000004",
                                             "1e-7"};
      return kNumbers[rng.Int(0, 19)];
    }
    case 3: {
      // Escapes (\u left to nlohmann by the plain reader), raw UTF-8 of every length, DEL.
      static const char* const kStrings[] = {
          "\"\\ud83d\\ude00 \\n \\/\"",
          "\"plain\"",
          "\"a\\\"b\\\\c\\b\\f\\n\\r\\t\\/\"",
          "\"\xC3\xA9\xE3\x81\x82\xED\x9F\xBF\xEE\x80\x80\xF0\x9F\x98\x80\xF4\x8F\xBF\xBF\"",
          "\"\x7F~ \"",
          "\"\""};
      return kStrings[rng.Int(0, 5)];
    }
    case 4:
      return rng.OneIn(2) ? "true" : (rng.OneIn(2) ? "false" : "null");
    case 5:
      return rng.OneIn(2) ? "{}" : " [ ] ";
    case 6:
    case 7: {
      const int n = rng.OneIn(4) ? rng.Int(17, 40) : rng.Int(1, 6);
      std::string out = "{";
      for (int i = 0; i < n; ++i) {
        absl::StrAppend(&out, i ? "," : "", "\"", RandomKey(rng, n),
                        "\" :", RandomJson(rng, depth - 1));
      }
      return out + "}";
    }
    default: {
      const int n = rng.Int(1, 8);
      std::string out = "[";
      for (int i = 0; i < n; ++i) absl::StrAppend(&out, i ? ",\n" : "", RandomJson(rng, depth - 1));
      return out + "]";
    }
  }
}

// Same types everywhere (dump alone would not tell 5 as an integer from 5 as unsigned).
void ExpectSameTree(const Json& a, const Json& b, const std::string& path) {
  ASSERT_EQ(a.type(), b.type()) << path;
  if (a.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    auto i = a.begin();
    auto j = b.begin();
    for (; i != a.end(); ++i, ++j) {
      ASSERT_EQ(i.key(), j.key()) << path;
      ExpectSameTree(i.value(), j.value(), path + "." + i.key());
    }
  } else if (a.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << path;
    for (size_t k = 0; k < a.size(); ++k)
      ExpectSameTree(a[k], b[k], absl::StrCat(path, "[", k, "]"));
  }
}

void ExpectSameParse(const std::string& text) {
  const absl::StatusOr<Json> fast = ParseJsonText(text);
  const absl::StatusOr<Json> dom = ParseJsonTextByDom(text);
  ASSERT_EQ(fast.status(), dom.status()) << text;
  if (!dom.ok()) return;
  EXPECT_EQ(fast->dump(), dom->dump()) << text;
  ExpectSameTree(*fast, *dom, "");
}

TEST(JsonTextParseTest, SameDocumentAsNlohmannsParserOnRandomText) {
  SplitMix64 rng(0x15);
  int ok = 0, errors = 0;
  for (int round = 0; round < 3000; ++round) {
    std::string text = RandomJson(rng, 4);
    switch (rng.Int(0, 6)) {
      case 0:  // cut short
        text.resize(static_cast<size_t>(rng.Int(0, static_cast<int>(text.size()))));
        break;
      case 1:  // a stray byte
        text.insert(static_cast<size_t>(rng.Int(0, static_cast<int>(text.size()))), 1,
                    "}]:,x\"\x01"[rng.Int(0, 6)]);
        break;
      case 4: {  // a stray or broken sequence (bad UTF-8, a BOM, a number's pieces)
        static const char* const kBroken[] = {"\x80",
                                              "\xC3",
                                              "\xC0\xAF",
                                              "\xE0\x80\xAF",
                                              "\xED\xA0\x80",
                                              "\xF4\x90\x80\x80",
                                              "\xF5",
                                              "\xEF\xBB\xBF",
                                              "0",
                                              "-",
                                              ".",
                                              "e",
                                              "+",
                                              "\\u12",
                                              "\\x",
                                              "\t",
                                              "\r\n",
                                              "\x1F"};
        const int at = rng.Int(0, static_cast<int>(text.size()));
        text.insert(static_cast<size_t>(rng.OneIn(4) ? 0 : at), kBroken[rng.Int(0, 17)]);
        break;
      }
      case 2:
        text += rng.OneIn(2) ? " 1" : " 1e999";
        break;
      case 3:
        text = absl::StrCat("[", text, ",1e999]");
        break;
      default:
        break;
    }
    ExpectSameParse(text);
    if (ParseJsonTextByDom(text).ok())
      ++ok;
    else
      ++errors;
  }
  EXPECT_GT(ok, 1000);
  EXPECT_GT(errors, 500);
}

TEST(JsonTextParseTest, SameDocumentOnTheTestFiles) {
  for (const std::string path :
       {KOMA_TESTDATA_DIR "/spine/matt-3.7.json", KOMA_TESTDATA_DIR "/spine/hero-3.8.json",
        KOMA_TESTDATA_DIR "/spine/hero-4.1.json", KOMA_TESTDATA_DIR "/spine/hero-4.2.json",
        KOMA_SAMPLES_DIR "/hero.json", KOMA_SAMPLES_DIR "/arm_head.motion3.json",
        KOMA_TESTDATA_DIR "/small.motion3.json"}) {
    const std::string text = ReadTestFile(path);
    ASSERT_THAT(ParseJsonText(text).status(), IsOk()) << path;
    ExpectSameParse(text);
  }
}

// A call stopped by its signal (core/stop_check.h) ends the parse with the signal's status,
// on both paths (the fast reader and, for text it leaves to nlohmann, nlohmann's SAX parser).
class AlwaysStop final : public StopSignal {
 public:
  absl::Status Reason() const override { return absl::CancelledError("stopped for the test"); }
};

TEST(JsonTextParseTest, AStoppedCallEndsTheParseWithItsStatus) {
  std::string plain = "[";
  for (int i = 0; i < 200000; ++i) absl::StrAppend(&plain, i == 0 ? "" : ",", i);
  plain += "]";
  // With a byte order mark the fast reader leaves the text to nlohmann's parser.
  const std::string with_bom = "\xEF\xBB\xBF" + plain;
  const AlwaysStop stop;
  const StopSignalScope scope(&stop);
  for (const std::string& text : {plain, with_bom}) {
    EXPECT_THAT(ParseJsonText(text).status(), StatusIs(absl::StatusCode::kCancelled, ::testing::_));
    EXPECT_THAT(ParseJsonTextWithin(text, 64).status(),
                StatusIs(absl::StatusCode::kCancelled, ::testing::_));
  }
  // Under 65,536 values the signal is never asked: small files are not slowed down.
  EXPECT_THAT(ParseJsonText("[1,2,3]"), IsOk());
}

TEST(JsonTextParseTest, AKeyGivenTwiceKeepsItsFirstPlaceAndLastValue) {
  std::string big = "{";
  for (int i = 0; i < 30; ++i) absl::StrAppend(&big, "\"k", i, "\":", i, ",");
  big += "\"k3\":{\"z\":1},\"k29\":[2],\"new\":0}";
  for (const std::string& text : {std::string("{\"a\":1,\"b\":2,\"a\":{\"c\":3}}"), big}) {
    ExpectSameParse(text);
  }
  const Json small = *ParseJsonText("{\"a\":1,\"b\":2,\"a\":{\"c\":3}}");
  EXPECT_EQ(small.dump(), "{\"a\":{\"c\":3},\"b\":2}");
  const Json large = *ParseJsonText(big);
  EXPECT_EQ(large.size(), 31u);
  EXPECT_EQ(large.begin().key(), "k0");
  EXPECT_EQ(large["k3"].dump(), "{\"z\":1}");
  EXPECT_EQ(large["k29"].dump(), "[2]");
  EXPECT_EQ((--large.end()).key(), "new");
}

}  // namespace
}  // namespace koma::formats

namespace koma::formats {
namespace {

// ParseJsonTextWithin(text, d) is CheckJsonDepth(text, d) then ParseJsonText(text): same
// status, same document, on random texts (some broken) at limits around their depth.
TEST(JsonTextParseTest, WithinIsTheDepthCheckThenTheParse) {
  SplitMix64 rng(0x32);
  int too_deep = 0;
  for (int round = 0; round < 1000; ++round) {
    std::string text = RandomJson(rng, 5);
    if (rng.OneIn(4)) text.resize(static_cast<size_t>(rng.Int(0, static_cast<int>(text.size()))));
    if (rng.OneIn(6)) text.insert(0, "\xEF\xBB\xBF");
    const int max_depth = rng.Int(1, 6);
    const absl::StatusOr<Json> within = ParseJsonTextWithin(text, max_depth);
    absl::Status expected = CheckJsonDepth(text, max_depth);
    if (!expected.ok()) ++too_deep;
    absl::StatusOr<Json> two_steps =
        expected.ok() ? ParseJsonText(text) : absl::StatusOr<Json>(expected);
    ASSERT_EQ(within.status(), two_steps.status()) << text;
    if (!within.ok()) continue;
    EXPECT_EQ(within->dump(), two_steps->dump()) << text;
    ExpectSameTree(*within, *two_steps, "");
  }
  EXPECT_GT(too_deep, 100);
}

}  // namespace
}  // namespace koma::formats

namespace koma::formats {
namespace {

// Every byte, and every pair of bytes, inside a string and as a stray token, and every
// three-byte sequence a UTF-8 lead byte from 0xE0 can start (with the boundary continuation
// bytes): the plain reader takes exactly the strings nlohmann takes (control characters,
// well-formed UTF-8 only), and leaves the rest to it.
TEST(JsonTextParseTest, EveryShortByteSequenceAsNlohmannReadsIt) {
  const auto expect_same = [](const std::string& text) {
    const absl::StatusOr<Json> fast = ParseJsonText(text);
    const absl::StatusOr<Json> dom = ParseJsonTextByDom(text);
    ASSERT_EQ(fast.status(), dom.status()) << text;
    if (dom.ok()) {
      ASSERT_EQ(fast->dump(), dom->dump()) << text;
    }
  };
  for (int a = 0; a < 256; ++a) {
    const std::string one(1, static_cast<char>(a));
    ASSERT_NO_FATAL_FAILURE(expect_same("[\"" + one + "\"]"));
    ASSERT_NO_FATAL_FAILURE(expect_same("[1" + one + "]"));
    ASSERT_NO_FATAL_FAILURE(expect_same("[\"\\" + one + "\"]"));
    for (int b = 0; b < 256; ++b) {
      ASSERT_NO_FATAL_FAILURE(expect_same("{\"k\":\"" + one + static_cast<char>(b) + "\"}"));
    }
  }
  const int kEdges[] = {0x00, 0x7F, 0x80, 0x8F, 0x90, 0x9F, 0xA0, 0xBF, 0xC0, 0xFF};
  for (int a = 0xE0; a < 256; ++a) {
    for (int b : kEdges) {
      for (int c : kEdges) {
        for (int d : {0x80, 0xBF, 0x22}) {
          std::string text = "[\"";
          for (int byte : {a, b, c, d}) text += static_cast<char>(byte);
          ASSERT_NO_FATAL_FAILURE(expect_same(text + "\"]"));
        }
      }
    }
  }
}

}  // namespace
}  // namespace koma::formats

// WriteSpine (walks the parsed document, dumping everything off the replaced path with
// nlohmann's serializer) against WriteSpineByDump (copies the document, replaces the timelines,
// dumps the copy): the same bytes on random skeletons of every version, with random unknown
// fields (escapes, non-ASCII text, odd number spellings, empty objects and arrays), several
// animations, random replacements (some equal to the old keys, so that timeline is kept) and on
// the test skeletons and the sample.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/curves.h"
#include "core/split_mix64.h"
#include "formats/spine.h"
#include "tests/formats/test_files.h"
#include "tests/testing/status_matchers.h"

namespace koma::formats {
namespace {

using ::koma::testing::IsOk;

// A random number in one of the spellings files use: integers, decimals, exponents, -0.
std::string RandomNumber(SplitMix64& rng, double lo, double hi) {
  const double x = lo + (hi - lo) * rng.Unit();
  switch (rng.Int(0, 5)) {
    case 0:
      return absl::StrCat(static_cast<int>(x));
    case 1:
      return absl::StrCat(x);
    case 2:
      return absl::StrCat(x, "e0");
    case 3:
      return rng.OneIn(2) ? "-0" : "0.0";
    case 4:
      return absl::StrCat(static_cast<int>(x), ".50");
    default: {
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.17g", x);
      return buffer;
    }
  }
}

std::string RandomText(SplitMix64& rng) {
  static const char* const kPieces[] = {"a",       "walk",   "\\\"q\\\"", "\\\\",  "\\n",
                                        "\\u00e9", "\xC3\xA9", "\\/",     "\\t",   "\\u0001",
                                        "\xE3\x81\x82", "x y",  "\\ud83d\\ude00"};
  std::string out;
  const int n = rng.Int(0, 4);
  for (int i = 0; i < n; ++i) out += kPieces[rng.Int(0, 12)];
  return out;
}

// An unknown value, up to `depth` levels deep.
std::string RandomValue(SplitMix64& rng, int depth) {
  switch (rng.Int(0, depth > 0 ? 7 : 4)) {
    case 0:
      return RandomNumber(rng, -1000, 1000);
    case 1:
      return absl::StrCat("\"", RandomText(rng), "\"");
    case 2:
      return rng.OneIn(2) ? "true" : "false";
    case 3:
      return "null";
    case 4:
      return rng.OneIn(2) ? "{}" : "[]";
    case 5:
    case 6: {
      std::string out = "{";
      const int n = rng.Int(1, 3);
      for (int i = 0; i < n; ++i) {
        absl::StrAppend(&out, i ? "," : "", "\"k", i, RandomText(rng), "\":",
                        RandomValue(rng, depth - 1));
      }
      return out + "}";
    }
    default: {
      std::string out = "[";
      const int n = rng.Int(1, 3);
      for (int i = 0; i < n; ++i) absl::StrAppend(&out, i ? "," : "", RandomValue(rng, depth - 1));
      return out + "]";
    }
  }
}

// `,"extraN": value` members, sometimes none.
std::string Extras(SplitMix64& rng) {
  std::string out;
  const int n = rng.OneIn(2) ? 0 : rng.Int(1, 2);
  for (int i = 0; i < n; ++i) {
    absl::StrAppend(&out, ",\"extra", i, RandomText(rng), "\":", RandomValue(rng, 2));
  }
  return out;
}

// One timeline's keys: times increasing from 0 or later, curves of every kind for the version.
std::string RandomKeys(SplitMix64& rng, int major, int minor, const std::vector<std::string>& fields,
                       double fps) {
  std::string out = "[";
  const int n = rng.Int(1, 6);
  double t = rng.OneIn(3) ? 0.0 : rng.Int(0, 10) / fps;
  for (int k = 0; k < n; ++k) {
    const double next = t + rng.Int(1, 20) / fps + (rng.OneIn(4) ? 0.013 : 0.0);
    std::string key = "{";
    if (t != 0.0 || rng.OneIn(2)) absl::StrAppend(&key, "\"time\":", t, ",");
    for (const std::string& field : fields) absl::StrAppend(&key, "\"", field, "\":", RandomNumber(rng, -50, 50), ",");
    if (k + 1 < n) {
      switch (rng.Int(0, 3)) {
        case 0:
          break;
        case 1:
          absl::StrAppend(&key, "\"curve\":\"stepped\",");
          break;
        case 2:
          absl::StrAppend(&key, "\"curve\":\"linear\",");
          break;
        default:
          if (major == 3 && minor == 8) {
            absl::StrAppend(&key, "\"curve\":", rng.Unit(), ",\"c2\":", rng.Unit(), ",\"c3\":",
                            rng.Unit(), ",\"c4\":", rng.Unit(), ",");
          } else if (major == 3) {
            absl::StrAppend(&key, "\"curve\":[", rng.Unit(), ",", rng.Unit(), ",", rng.Unit(), ",",
                            rng.Unit(), "],");
          } else {
            key += "\"curve\":[";
            for (size_t v = 0; v < fields.size(); ++v) {
              absl::StrAppend(&key, v ? "," : "", t + (next - t) * rng.Unit(), ",",
                              RandomNumber(rng, -50, 50), ",", t + (next - t) * rng.Unit(), ",",
                              RandomNumber(rng, -50, 50));
            }
            key += "],";
          }
      }
    }
    if (rng.OneIn(4)) absl::StrAppend(&key, "\"note\":", RandomValue(rng, 1), ",");
    key.back() = '}';
    absl::StrAppend(&out, k ? "," : "", key);
    t = next;
  }
  return out + "]";
}

std::string RandomSkeleton(SplitMix64& rng) {
  static const char* const kVersions[] = {"3.7.94", "3.8.99", "4.0.64", "4.1.24", "4.2.18"};
  const std::string version = kVersions[rng.Int(0, 4)];
  const int major = version[0] - '0', minor = version[2] - '0';
  const double fps = rng.OneIn(2) ? 30.0 : 24.0;
  std::string out = absl::StrCat("{\"skeleton\":{\"hash\":\"", RandomText(rng), "\",\"spine\":\"",
                                 version, "\"", fps == 30.0 && rng.OneIn(2) ? "" : ",\"fps\":", "");
  if (out.back() == ':') absl::StrAppend(&out, fps);
  out += "}";
  const int bones = rng.Int(1, 6);
  out += ",\"bones\":[{\"name\":\"root\"}";
  for (int b = 1; b < bones; ++b) absl::StrAppend(&out, ",{\"name\":\"b", b, "\",\"parent\":\"root\"", Extras(rng), "}");
  out += "]";
  out += Extras(rng);
  out += ",\"animations\":{";
  const int animations = rng.Int(1, 3);
  for (int a = 0; a < animations; ++a) {
    absl::StrAppend(&out, a ? "," : "", "\"anim", a, RandomText(rng), "\":{");
    std::string members;
    if (rng.OneIn(3)) absl::StrAppend(&members, "\"slots\":", RandomValue(rng, 2), ",");
    members += "\"bones\":{";
    bool first_bone = true;
    for (int b = 0; b < bones; ++b) {
      if (rng.OneIn(3)) continue;
      absl::StrAppend(&members, first_bone ? "" : ",", "\"", b == 0 ? std::string("root") : absl::StrCat("b", b), "\":{");
      first_bone = false;
      std::vector<std::pair<std::string, std::vector<std::string>>> timelines;
      const std::string rotate_field = major == 3 ? "angle" : "value";
      if (rng.OneIn(2)) timelines.push_back({"rotate", {rotate_field}});
      for (const char* t : {"translate", "scale", "shear"}) {
        if (major == 4 && rng.OneIn(3)) {
          if (rng.OneIn(2)) timelines.push_back({std::string(t) + "x", {"value"}});
          if (rng.OneIn(2)) timelines.push_back({std::string(t) + "y", {"value"}});
        } else if (rng.OneIn(2)) {
          timelines.push_back({t, {"x", "y"}});
        }
      }
      if (rng.OneIn(4)) timelines.push_back({"inherit", {}});
      bool first = true;
      for (const auto& [name, fields] : timelines) {
        absl::StrAppend(&members, first ? "" : ",", "\"", name, "\":",
                        fields.empty() ? "[{\"inherit\":\"noScale\"}]"
                                       : RandomKeys(rng, major, minor, fields, fps));
        first = false;
      }
      members += "}";
    }
    members += "}";
    if (rng.OneIn(3)) absl::StrAppend(&members, ",\"events\":[{\"time\":", rng.Int(0, 40) / fps, ",\"name\":\"e\"}]");
    absl::StrAppend(&out, members, Extras(rng), "}");
  }
  out += "}";
  out += Extras(rng);
  return out + "}";
}

// Random replacements for every animation: a curve's own stepped keys (when it is stepped:
// "nothing to change"), new stepped keys, or none.
std::vector<SpineRetimed> RandomRetimes(SplitMix64& rng, const SpineFile& file) {
  std::vector<SpineRetimed> out;
  for (size_t a = 0; a < file.animations.size(); ++a) {
    if (rng.OneIn(3)) continue;
    const SpineAnimation& animation = file.animations[a];
    SpineRetimed one;
    one.animation = static_cast<int>(a);
    for (const Curve& curve : animation.curves.curves) {
      const int choice = rng.Int(0, 3);
      if (choice == 0) {
        one.stepped.push_back(std::nullopt);
      } else if (choice == 1) {
        std::vector<CurvePoint> own{curve.start};
        for (const CurveSegment& segment : curve.segments) own.push_back(segment.end);
        one.stepped.push_back(own);
      } else {
        std::vector<CurvePoint> steps;
        double frame = rng.Int(0, 3);
        const int n = rng.Int(1, 12);
        for (int k = 0; k < n; ++k) {
          steps.push_back({frame, rng.OneIn(5) ? 1.0 : 100 * rng.Unit() - 50});
          frame += rng.OneIn(3) ? 2.5 : rng.Int(1, 4);
        }
        one.stepped.push_back(steps);
      }
    }
    out.push_back(std::move(one));
    if (rng.OneIn(6)) out.push_back(out.back());  // the same animation twice
  }
  return out;
}

void ExpectSameAsByDump(const SpineFile& file, const std::vector<SpineRetimed>& retimed,
                        const std::string& what) {
  absl::StatusOr<std::string> walked = WriteSpine(file, retimed);
  absl::StatusOr<std::string> dumped = WriteSpineByDump(file, retimed);
  ASSERT_THAT(dumped.status(), IsOk()) << what;
  ASSERT_THAT(walked.status(), IsOk()) << what;
  EXPECT_EQ(*walked, *dumped) << what;
}

TEST(SpineWriteWalkTest, SameBytesAsDumpingAnEditedCopyOnRandomSkeletons) {
  SplitMix64 rng(0x5B1E);
  int compared = 0, replaced = 0;
  for (int round = 0; round < 400; ++round) {
    const std::string text = RandomSkeleton(rng);
    absl::StatusOr<SpineFile> file = ParseSpine(text);
    ASSERT_THAT(file.status(), IsOk()) << text;
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<SpineRetimed> retimed = RandomRetimes(rng, *file);
      ExpectSameAsByDump(*file, retimed, text);
      ++compared;
      const std::string plain = *WriteSpine(*file, {});
      if (*WriteSpine(*file, retimed) != plain) ++replaced;
    }
  }
  EXPECT_EQ(compared, 1200);
  EXPECT_GT(replaced, 600);  // most trials replace something
}

TEST(SpineWriteWalkTest, SameBytesOnTheTestSkeletonsAndTheSample) {
  SplitMix64 rng(7);
  for (const std::string path :
       {KOMA_TESTDATA_DIR "/spine/matt-3.7.json", KOMA_TESTDATA_DIR "/spine/hero-3.8.json",
        KOMA_TESTDATA_DIR "/spine/hero-4.1.json", KOMA_TESTDATA_DIR "/spine/hero-4.2.json",
        KOMA_SAMPLES_DIR "/hero.json"}) {
    absl::StatusOr<SpineFile> file = ParseSpine(ReadTestFile(path));
    ASSERT_THAT(file.status(), IsOk()) << path;
    ExpectSameAsByDump(*file, {}, path);
    for (int trial = 0; trial < 20; ++trial) ExpectSameAsByDump(*file, RandomRetimes(rng, *file), path);
  }
}

TEST(SpineWriteWalkTest, RefusesWhatTheReferenceRefuses) {
  absl::StatusOr<SpineFile> file = ParseSpine(ReadTestFile(KOMA_TESTDATA_DIR "/spine/hero-4.1.json"));
  ASSERT_THAT(file.status(), IsOk());
  const std::vector<std::vector<SpineRetimed>> bad = {
      {SpineRetimed{99, {}}},
      {SpineRetimed{0, {std::nullopt}}},
  };
  for (const std::vector<SpineRetimed>& retimed : bad) {
    EXPECT_EQ(WriteSpine(*file, retimed).status(), WriteSpineByDump(*file, retimed).status());
    EXPECT_FALSE(WriteSpine(*file, retimed).ok());
  }
}

}  // namespace
}  // namespace koma::formats

// Timing groups of RetimeCurves (docs/semantics.md, "Timing groups"): id patterns, the default
// grouping of Live2D's standard ids, and the property that a group's timing depends only on
// its own curves (each group answers as its curves alone would).
#include "core/timing_groups.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "core/koma_uchi.h"
#include "core/split_mix64.h"
#include "tests/testing/live2d_motion.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(IdMatchesTest, StarsQuestionMarksAndExactIds) {
  EXPECT_TRUE(IdMatches("ParamHair*", "ParamHairFront"));
  EXPECT_TRUE(IdMatches("ParamHair*", "ParamHair"));
  EXPECT_FALSE(IdMatches("ParamHair*", "ParamHai"));
  EXPECT_TRUE(IdMatches("Param*Open", "ParamEyeLOpen"));
  EXPECT_TRUE(IdMatches("Param*Open*", "ParamEyeLOpenOpen"));
  EXPECT_FALSE(IdMatches("Param*Open", "ParamEyeLOpenX"));
  EXPECT_TRUE(IdMatches("ParamEye?Open", "ParamEyeROpen"));
  EXPECT_FALSE(IdMatches("ParamEye?Open", "ParamEyeOpen"));
  EXPECT_TRUE(IdMatches("*", ""));
  EXPECT_TRUE(IdMatches("ParamCheek", "ParamCheek"));
  EXPECT_FALSE(IdMatches("ParamCheek", "ParamCheeks"));
  EXPECT_FALSE(IdMatches("paramcheek", "ParamCheek"));  // case-sensitive, as Live2D ids
  EXPECT_TRUE(IdMatches("*a*a*a*b", "aaaaaaaaaaaaaaaaaaab"));
  EXPECT_FALSE(IdMatches("*a*a*a*b", "aaaaaaaaaaaaaaaaaaaa"));
}

// A naive matcher: try every split (exponential, on short strings only).
bool NaiveMatches(const std::string& p, const std::string& s) {
  if (p.empty()) return s.empty();
  if (p[0] == '*') {
    for (size_t k = 0; k <= s.size(); ++k) {
      if (NaiveMatches(p.substr(1), s.substr(k))) return true;
    }
    return false;
  }
  return !s.empty() && (p[0] == '?' || p[0] == s[0]) && NaiveMatches(p.substr(1), s.substr(1));
}

TEST(IdMatchesTest, AgreesWithNaiveMatcher) {
  SplitMix64 rng(29);
  const std::string pattern_chars = "ab*?";
  for (int i = 0; i < 20000; ++i) {
    std::string p, s;
    for (int k = rng.Int(0, 6); k > 0; --k) p += pattern_chars[rng.Int(0, 3)];
    for (int k = rng.Int(0, 8); k > 0; --k) s += "ab"[rng.Int(0, 1)];
    ASSERT_EQ(IdMatches(p, s), NaiveMatches(p, s)) << "\"" << p << "\" vs \"" << s << "\"";
  }
}

// The default grouping on docs.live2d.com's standard parameter list (and custom ids).
TEST(DefaultTimingGroupsTest, StandardIdsGoToFaceHairOrBody) {
  const std::vector<CurveTimingGroup> groups = DefaultLive2dTimingGroups();
  const auto group_of = [&groups](const std::string& id) {
    const int g = GroupOf(groups, id);
    return g == static_cast<int>(groups.size()) ? std::string(kDefaultTimingGroupName)
                                                : groups[g].name;
  };
  const std::map<std::string, std::vector<std::string>> want = {
      {"face",
       {"ParamEyeLOpen", "ParamEyeROpen", "ParamEyeLSmile", "ParamEyeRSmile", "ParamEyeBallX",
        "ParamEyeBallY", "ParamEyeBallForm", "ParamBrowLY", "ParamBrowRY", "ParamBrowLX",
        "ParamBrowRX", "ParamBrowLAngle", "ParamBrowRAngle", "ParamBrowLForm", "ParamBrowRForm",
        "ParamMouthForm", "ParamMouthOpenY", "ParamCheek"}},
      {"hair",
       {"ParamHairFront", "ParamHairSide", "ParamHairBack", "ParamHairFluffy", "ParamBustX",
        "ParamBustY"}},
      {"body",
       {"ParamAngleX", "ParamAngleY", "ParamAngleZ", "ParamBodyAngleX", "ParamBodyAngleY",
        "ParamBodyAngleZ", "ParamBreath", "ParamArmLA", "ParamArmRA", "ParamArmLB", "ParamArmRB",
        "ParamHandL", "ParamHandR", "ParamShoulderY", "ParamBaseX", "ParamBaseY", "MyCustom",
        "PARAM_EYE_L_OPEN"}},
  };
  for (const auto& [name, ids] : want) {
    for (const std::string& id : ids) EXPECT_EQ(group_of(id), name) << id;
  }
  // The face is LipBlink's (its mouth and eyes drawn as LipBlink draws them), the hair stepped.
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].mode, TimingGroupMode::kLipBlink);
  EXPECT_EQ(groups[1].mode, TimingGroupMode::kStep);
}

TEST(TimingGroupsTest, FirstMatchingGroupWins) {
  std::vector<CurveTimingGroup> groups(2);
  groups[0].name = "eyes";
  groups[0].ids = {"ParamEye?Open"};
  groups[1].name = "face";
  groups[1].ids = {"ParamEye*", "ParamMouth*"};
  EXPECT_EQ(GroupOf(groups, "ParamEyeLOpen"), 0);
  EXPECT_EQ(GroupOf(groups, "ParamEyeLSmile"), 1);
  EXPECT_EQ(GroupOf(groups, "ParamMouthForm"), 1);
  EXPECT_EQ(GroupOf(groups, "ParamAngleX"), 2);
}

KomaUchiResult Retime(const CurveSet& set, const KomaUchiOptions& options) {
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
  EXPECT_THAT(ValidateKomaUchiOptions(options, set), IsOk());
  return RetimeCurves(set, options);
}

// The curves of `set` at `indices`, alone.
CurveSet Subset(const CurveSet& set, const std::vector<int>& indices) {
  CurveSet out = set;
  out.curves.clear();
  for (int c : indices) out.curves.push_back(set.curves[c]);
  return out;
}

// Every group answers exactly as its curves alone, timed with the group's options, would: key
// poses, timings and values. So a group's timing depends only on its own curves, and changing
// or removing the other groups' curves cannot change it.
TEST(TimingGroupsTest, EachGroupAnswersAsItsCurvesAlone) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    for (double fps : {30.0, 60.0}) {
      const CurveSet set = testing::Live2dMotion({fps, 45, 3.0, seed});
      KomaUchiOptions options;
      options.timing_fps = seed % 3 == 0 ? 0.0 : 24.0;
      options.groups = DefaultLive2dTimingGroups();
      options.groups[1].frames_per_drawing = 2;  // hair on twos
      options.groups[0].tame = 1.5;
      options.curve_frames_per_drawing["ParamArmLA"] = 1;
      const KomaUchiResult result = Retime(set, options);
      ASSERT_EQ(result.groups.size(), 3u);
      EXPECT_EQ(result.groups[0].name, "body");
      EXPECT_EQ(result.groups[1].name, "face");
      EXPECT_EQ(result.groups[2].name, "hair");
      EXPECT_EQ(result.groups[2].frames_per_drawing, 2);
      EXPECT_EQ(result.key_frames, result.groups[0].key_frames);
      const std::vector<std::vector<int>> members = GroupMembers(options, set);
      for (size_t g = 0; g < result.groups.size(); ++g) {
        const std::vector<int>& curves = g == 0 ? members.back() : members[g - 1];
        EXPECT_EQ(result.groups[g].curves, curves);
        KomaUchiOptions alone = g == 0 ? options : GroupOptions(options, options.groups[g - 1]);
        alone.groups.clear();
        const CurveSet subset = Subset(set, curves);
        alone.curve_frames_per_drawing.clear();  // only those of the group's own curves
        for (const Curve& c : subset.curves) {
          const auto own = options.curve_frames_per_drawing.find(c.id);
          if (own != options.curve_frames_per_drawing.end()) {
            alone.curve_frames_per_drawing.insert(*own);
          }
        }
        const KomaUchiResult want = Retime(subset, alone);
        EXPECT_EQ(result.groups[g].key_frames, want.key_frames) << "group " << g;
        EXPECT_EQ(result.groups[g].key_grid_frames, want.key_grid_frames);
        EXPECT_EQ(result.groups[g].key_merged, want.key_merged);
        for (size_t i = 0; i < curves.size(); ++i) {
          const RetimedCurve& got = result.curves[curves[i]];
          EXPECT_EQ(got.values, want.curves[i].values) << set.curves[curves[i]].id;
          EXPECT_EQ(got.hold_histogram, want.curves[i].hold_histogram);
          const DrawingTiming& a = result.timings[got.timing];
          const DrawingTiming& b = want.timings[want.curves[i].timing];
          EXPECT_EQ(a.drawing_of_frame, b.drawing_of_frame);
          EXPECT_EQ(a.drawing_start_grid, b.drawing_start_grid);
          EXPECT_EQ(a.frames_per_drawing, b.frames_per_drawing);
        }
      }
    }
  }
}

// Changing another group's curves (their keys, or dropping them) leaves a group's answer.
TEST(TimingGroupsTest, OtherGroupsCurvesDoNotChangeAGroup) {
  const CurveSet set = testing::Live2dMotion({30.0, 60, 4.0, 7});
  KomaUchiOptions options;
  options.timing_fps = 24.0;
  options.groups = DefaultLive2dTimingGroups();
  CurveSet changed = set;
  for (Curve& curve : changed.curves) {
    if (GroupOf(options.groups, curve.id) == 0) continue;  // keep the face
    for (CurveSegment& s : curve.segments) s.end.value += 0.25;
    if (curve.segments.size() > 2) curve.segments.erase(curve.segments.begin());
  }
  changed.curves.push_back(testing::Live2dMotion({30.0, 40, 4.0, 8}).curves[20]);
  changed.curves.back().id = "ParamBodyExtra";
  const KomaUchiResult a = Retime(set, options);
  const KomaUchiResult b = Retime(changed, options);
  ASSERT_EQ(a.groups[1].name, "face");
  EXPECT_EQ(a.groups[1].key_frames, b.groups[1].key_frames);
  EXPECT_EQ(a.groups[1].curves, b.groups[1].curves);
  EXPECT_NE(a.groups[0].key_frames, b.groups[0].key_frames);  // the body did change
  for (int c : a.groups[1].curves) {
    EXPECT_EQ(a.curves[c].values, b.curves[c].values) << set.curves[c].id;
    EXPECT_EQ(a.curves[c].steps.size(), b.curves[c].steps.size());
  }
}

// Curves all in the default group: the answer is the ungrouped one, with no group listed.
TEST(TimingGroupsTest, AllCurvesInTheDefaultGroupAnswerAsNoGroups) {
  CurveSet set = testing::Live2dMotion({30.0, 40, 3.0, 3});
  for (size_t c = 0; c < set.curves.size(); ++c) set.curves[c].id = "P" + std::to_string(c);
  KomaUchiOptions grouped;
  grouped.groups = DefaultLive2dTimingGroups();
  const KomaUchiResult a = Retime(set, grouped);
  const KomaUchiResult b = Retime(set, KomaUchiOptions());
  EXPECT_TRUE(a.groups.empty());
  EXPECT_EQ(a.key_frames, b.key_frames);
  EXPECT_EQ(a.key_merged, b.key_merged);
  ASSERT_EQ(a.timings.size(), b.timings.size());
  EXPECT_EQ(a.timings[0].drawing_of_frame, b.timings[0].drawing_of_frame);
  for (size_t c = 0; c < set.curves.size(); ++c) EXPECT_EQ(a.curves[c].values, b.curves[c].values);
}

// A group's named key poses are taken as they are; a group matching no curve is listed empty.
TEST(TimingGroupsTest, NamedGroupKeysAndEmptyGroups) {
  const CurveSet set = testing::Live2dMotion({30.0, 40, 3.0, 4});
  KomaUchiOptions options;
  options.timing_fps = 0.0;
  options.groups = DefaultLive2dTimingGroups();
  options.groups[0].key_frames = {5, 6, 50};
  CurveTimingGroup none;
  none.name = "tail";
  none.ids = {"ParamTail*"};
  options.groups.push_back(none);
  const KomaUchiResult result = Retime(set, options);
  ASSERT_EQ(result.groups.size(), 4u);
  EXPECT_THAT(result.groups[1].key_frames, ElementsAre(0, 5, 6, 50, set.frame_count - 1));
  EXPECT_TRUE(result.groups[1].key_merged.empty());
  EXPECT_TRUE(result.groups[3].curves.empty());
  EXPECT_EQ(result.groups[3].name, "tail");
}

TEST(TimingGroupsTest, InvalidGroupsNameTheFieldAndValue) {
  const CurveSet set = testing::Live2dMotion({30.0, 40, 3.0, 5});
  const auto check = [&set](auto change, const std::string& message) {
    KomaUchiOptions options;
    options.groups = DefaultLive2dTimingGroups();
    change(options.groups);
    EXPECT_THAT(ValidateKomaUchiOptions(options, set),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(message)));
  };
  check([](auto& g) { g[1].name = ""; }, "timing_groups[1].name: required");
  check([](auto& g) { g[1].name = "face"; }, "timing_groups[1].name: \"face\" is already");
  check([](auto& g) { g[0].name = "body"; }, "timing_groups[0].name: \"body\" is the default");
  check([](auto& g) { g[0].ids.clear(); }, "timing_groups[0].ids: empty");
  check([](auto& g) { g[0].ids.push_back(""); }, "timing_groups[0].ids[4]: empty");
  check([](auto& g) { g[1].frames_per_drawing = 0; },
        "timing_groups[1].frames_per_drawing: 0 must be >= 1");
  check([](auto& g) { g[1].tame = 0.5; }, "timing_groups[1].tame: 0.5 must be");
  check([](auto& g) { g[0].tsume = -1; }, "timing_groups[0].tsume: -1 must be");
  check([](auto& g) { g[0].key_frames = {4, 3}; },
        "timing_groups[0].key_frames[1]: 3 must be greater than timing_groups[0].key_frames[0]");
  check([](auto& g) { g[0].key_frames = {100000}; }, "timing_groups[0].key_frames[0]: 100000");
}

// A kKeep group: its curves are the input at every frame, without steps or a timing, and the
// other groups answer exactly as when it is stepped.
TEST(TimingGroupsTest, KeptGroupIsTheInputAndLeavesTheOthers) {
  for (double fps : {30.0, 60.0}) {
    const CurveSet set = testing::Live2dMotion({fps, 60, 4.0, 9});
    KomaUchiOptions stepped;
    stepped.timing_fps = 24.0;
    stepped.groups = DefaultLive2dTimingGroups();
    stepped.groups[0].mode = TimingGroupMode::kStep;
    KomaUchiOptions kept = stepped;
    kept.groups[0].mode = TimingGroupMode::kKeep;
    const KomaUchiResult a = Retime(set, stepped);
    const KomaUchiResult b = Retime(set, kept);
    ASSERT_EQ(b.groups[1].name, "face");
    EXPECT_EQ(b.groups[1].timing, -1);
    EXPECT_EQ(b.groups[1].frames_per_drawing, 0);
    EXPECT_TRUE(b.groups[1].key_frames.empty());
    ASSERT_FALSE(b.groups[1].curves.empty());
    EXPECT_EQ(b.timings.size() + 1, a.timings.size());  // the face's timing is gone
    for (size_t c = 0; c < set.curves.size(); ++c) {
      const bool face = GroupOf(kept.groups, set.curves[c].id) == 0;
      if (face) {
        EXPECT_EQ(b.curves[c].timing, -1);
        EXPECT_TRUE(b.curves[c].steps.empty());
        EXPECT_TRUE(b.curves[c].hold_histogram.empty());
        EXPECT_EQ(b.curves[c].values,
                  SampleEveryFrame(set.curves[c], set.frame_count, set.beziers_restricted))
            << set.curves[c].id;
      } else {
        EXPECT_EQ(b.curves[c].values, a.curves[c].values) << set.curves[c].id;
        EXPECT_EQ(b.curves[c].steps.size(), a.curves[c].steps.size());
        EXPECT_EQ(b.curves[c].hold_histogram, a.curves[c].hold_histogram);
      }
    }
  }
}

}  // namespace
}  // namespace koma

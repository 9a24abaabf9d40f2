// RetimeCurves (docs/semantics.md, "RetimeCurves"): key poses, timings, overrides, the paper's
// experiment, random requests' invariants, and the options' validation. Holds and spacing
// alone: spacing_test.cc.
#include "core/koma_uchi.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/split_mix64.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;
using ::koma::testing::StatusIs;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Pair;

CurveSegment Seg(SegmentType type, double frame, double value) {
  CurveSegment segment;
  segment.type = type;
  segment.end = {frame, value};
  return segment;
}

Curve Keyframes(std::string id, CurvePoint start, std::vector<CurveSegment> segments) {
  Curve curve;
  curve.id = std::move(id);
  curve.start = start;
  curve.segments = std::move(segments);
  return curve;
}

// value = frame over [0, frame_count - 1]: the retimed values are the source times.
Curve Identity(const std::string& id, int frame_count) {
  const double last = frame_count - 1;
  return Keyframes(id, {0, 0}, {Seg(SegmentType::kLinear, last, last)});
}

CurveSet SetOf(int frame_count, std::vector<Curve> curves) {
  CurveSet set;
  set.frame_count = frame_count;
  set.curves = std::move(curves);
  return set;
}

KomaUchiResult Retime(const CurveSet& set, const KomaUchiOptions& options) {
  EXPECT_THAT(ValidateCurveSet(set), IsOk());
  EXPECT_THAT(ValidateKomaUchiOptions(options, set), IsOk());
  return RetimeCurves(set, options);
}

// Hold lengths of a timing, in drawing order.
std::vector<int> Holds(const DrawingTiming& timing) {
  std::vector<int> holds;
  const std::vector<int>& starts = timing.drawing_start;
  for (size_t d = 0; d < starts.size(); ++d) {
    const int end =
        d + 1 < starts.size() ? starts[d + 1] : static_cast<int>(timing.drawing_of_frame.size());
    holds.push_back(end - starts[d]);
  }
  return holds;
}

std::string HistogramText(const std::map<int, int>& histogram) {
  std::ostringstream text;
  for (const auto& [hold, count] : histogram) text << hold << "-frame holds: " << count << "; ";
  return text.str();
}

TEST(KeyPosesTest, DefaultIsEveryKeyframeTimeRoundedPlusFirstAndLast) {
  CurveSegment bezier = Seg(SegmentType::kBezier, 20.4, 1);
  bezier.handles[0] = {13, 0};  // handles are not key poses
  bezier.handles[1] = {17, 1};
  Curve dense;
  dense.id = "Dense";  // dense curves have no keyframes
  dense.samples.assign(41, 0.0);
  const CurveSet set =
      SetOf(41, {Keyframes("A", {0, 0}, {Seg(SegmentType::kLinear, 9.6, 1), bezier}),
                 Keyframes("B", {2.5, 0}, {Seg(SegmentType::kStepped, 150, 1)}),  // 2.5 -> 3
                 Keyframes("C", {-4, 0}, {Seg(SegmentType::kInverseStepped, 9.5, 1)}), dense});
  EXPECT_THAT(KeyPoses({}, set), ElementsAre(0, 3, 10, 20, 40));
}

TEST(KeyPosesTest, GivenKeysGetTheFirstAndLastFrame) {
  KomaUchiOptions options;
  options.key_frames = {10, 25};
  EXPECT_THAT(KeyPoses(options, SetOf(31, {Identity("A", 31)})), ElementsAre(0, 10, 25, 30));
  options.key_frames = {0, 30};
  EXPECT_THAT(KeyPoses(options, SetOf(31, {Identity("A", 31)})), ElementsAre(0, 30));
}

// Miyamune et al., section 4.1: key poses 0, 10, 25, 35, 50, 60, 75, 85, 100 on threes. The
// paper saw stray 1- and 4-frame holds; the even hold rule leaves 10-frame segments as
// 3, 3, 2, 2 and 15-frame ones as five 3s, plus the final key's own frame.
TEST(RetimeCurvesTest, PaperExperimentOnThrees) {
  const CurveSet set = SetOf(101, {Identity("ParamArmL", 101)});
  KomaUchiOptions options;
  options.key_frames = {0, 10, 25, 35, 50, 60, 75, 85, 100};
  const KomaUchiResult result = Retime(set, options);
  EXPECT_EQ(result.key_frames, options.key_frames);
  ASSERT_EQ(result.timings.size(), 1u);
  const DrawingTiming& timing = result.timings[0];
  const std::map<int, int>& histogram = result.curves[0].hold_histogram;
  std::cout << "paper experiment (on threes, 101 frames): " << HistogramText(histogram) << "\n";
  ::testing::Test::RecordProperty("hold_histogram", HistogramText(histogram));
  EXPECT_THAT(histogram, ElementsAre(Pair(1, 1), Pair(2, 8), Pair(3, 28)));
  for (int key : result.key_frames) {
    EXPECT_NE(std::find(timing.drawing_start.begin(), timing.drawing_start.end(), key),
              timing.drawing_start.end())
        << "key " << key << " does not start a drawing";
    EXPECT_EQ(timing.source_frame[key], key);
  }
  const std::vector<int> holds = Holds(timing);
  EXPECT_LE(*std::max_element(holds.begin(), holds.end()), 3);
  EXPECT_EQ(holds.size(), 37u);
  // Segment [0, 10]: holds 3, 3, 2, 2 sampling tau = 0, 2.5, 5, 7.5 (even spacing).
  const std::vector<double> first(result.curves[0].values.begin(),
                                  result.curves[0].values.begin() + 11);
  EXPECT_THAT(first, ElementsAre(0, 0, 0, 2.5, 2.5, 2.5, 5, 5, 7.5, 7.5, 10));
  EXPECT_THAT(
      std::vector<int>(timing.drawing_of_frame.begin(), timing.drawing_of_frame.begin() + 11),
      ElementsAre(0, 0, 0, 1, 1, 1, 2, 2, 3, 3, 4));
  EXPECT_EQ(timing.frames_per_drawing, 3);
  EXPECT_EQ(timing.drawing_of_frame.back(), 36);
  EXPECT_EQ(result.curves[0].values.back(), 100.0);
}

TEST(RetimeCurvesTest, TameAndTsumeMoveTheSamplesTowardTheKeys) {
  KomaUchiOptions options;
  options.key_frames = {0, 10, 20};
  options.tame = 2.0;
  options.tsume = 2.0;
  const KomaUchiResult result = Retime(SetOf(21, {Identity("A", 21)}), options);
  // D = 4, E = 0, 1/6, 1/2, 5/6 (SpacingTest.HandComputedValues) times L = 10.
  const std::vector<double>& v = result.curves[0].values;
  EXPECT_EQ(v[0], 0.0);
  EXPECT_NEAR(v[3], 10.0 / 6, 1e-12);
  EXPECT_NEAR(v[6], 5.0, 1e-12);
  EXPECT_NEAR(v[8], 50.0 / 6, 1e-12);
  EXPECT_EQ(v[10], 10.0);
  EXPECT_NEAR(v[13], 10.0 + 10.0 / 6, 1e-12);
}

TEST(RetimeCurvesTest, PerCurveFramesPerDrawingGetsItsOwnTiming) {
  const CurveSet set =
      SetOf(25, {Identity("ParamBody", 25), Identity("ParamHair", 25), Identity("ParamFace", 25)});
  KomaUchiOptions options;
  options.key_frames = {12};
  options.curve_frames_per_drawing = {{"ParamHair", 2}, {"ParamFace", 3}};  // 3 = default
  const KomaUchiResult result = Retime(set, options);
  ASSERT_EQ(result.timings.size(), 2u);  // ParamFace's n = 3 is timing 0 itself
  EXPECT_EQ(result.timings[0].frames_per_drawing, 3);
  EXPECT_EQ(result.timings[1].frames_per_drawing, 2);
  EXPECT_EQ(result.curves[0].timing, 0);
  EXPECT_EQ(result.curves[1].timing, 1);
  EXPECT_EQ(result.curves[2].timing, 0);
  EXPECT_THAT(result.curves[0].hold_histogram, ElementsAre(Pair(1, 1), Pair(3, 8)));
  EXPECT_THAT(result.curves[1].hold_histogram, ElementsAre(Pair(1, 1), Pair(2, 12)));
  EXPECT_EQ(result.curves[1].steps.size(), 13u);
  EXPECT_EQ(result.curves[1].values[2], 2.0);  // hair on twos: a new drawing at frame 2
  EXPECT_EQ(result.curves[0].values[2], 0.0);  // body still on its first drawing
}

TEST(RetimeCurvesTest, ACurvesOwnNIsLabelledEvenWhenOverridesMatchIt) {
  // Default n = 2, but both segments are overridden to 3: timing 0 is on threes throughout,
  // yet a curve that asked for n = 3 gets a timing of its own, labelled 3.
  KomaUchiOptions options;
  options.frames_per_drawing = 2;
  options.key_frames = {9};
  options.segment_overrides = {{0, 3, {}, {}}, {1, 3, {}, {}}};
  options.curve_frames_per_drawing = {{"Own", 3}};
  const KomaUchiResult result =
      Retime(SetOf(19, {Identity("Default", 19), Identity("Own", 19)}), options);
  ASSERT_EQ(result.timings.size(), 2u);
  EXPECT_EQ(result.timings[0].frames_per_drawing, 2);
  EXPECT_EQ(result.timings[1].frames_per_drawing, 3);
  EXPECT_EQ(result.curves[1].timing, 1);
  EXPECT_EQ(Holds(result.timings[0]), Holds(result.timings[1]));
}

TEST(RetimeCurvesTest, SegmentOverridesChangeOnlyTheirSegment) {
  KomaUchiOptions options;
  options.key_frames = {10};  // segments [0, 10], [10, 20]
  options.segment_overrides.push_back({1, 2, 2.0, std::nullopt});
  options.curve_frames_per_drawing = {{"Own", 3}};
  const KomaUchiResult result =
      Retime(SetOf(21, {Identity("Default", 21), Identity("Own", 21)}), options);
  ASSERT_EQ(result.timings.size(), 2u);
  EXPECT_THAT(Holds(result.timings[0]), ElementsAre(3, 3, 2, 2, 2, 2, 2, 2, 2, 1));
  // "Own" keeps n = 3 in segment 1 but the segment's tame still applies: E = Spacing(4, 2, 1).
  EXPECT_THAT(Holds(result.timings[1]), ElementsAre(3, 3, 2, 2, 3, 3, 2, 2, 1));
  const std::vector<double> own_e = Spacing(4, 2.0, 1.0);
  for (int j = 0; j < 4; ++j) {
    EXPECT_EQ(result.timings[1].source_frame[result.timings[1].drawing_start[4 + j]],
              10.0 + 10.0 * own_e[j]);
  }
  const std::vector<double> default_e = Spacing(5, 2.0, 1.0);
  for (int j = 0; j < 5; ++j) {
    EXPECT_EQ(result.timings[0].source_frame[result.timings[0].drawing_start[4 + j]],
              10.0 + 10.0 * default_e[j]);
  }
  EXPECT_EQ(result.timings[0].source_frame[3], 2.5);  // segment 0 untouched: even spacing
}

// A random valid set: keyframe curves of every segment type (some keys off-frame, some past
// the ends) and dense curves.
CurveSet RandomSet(SplitMix64& rng) {
  const int frame_count = rng.Int(2, 150);
  CurveSet set = SetOf(frame_count, {});
  set.beziers_restricted = !rng.OneIn(3);
  const int curves = rng.Int(1, 4);
  for (int c = 0; c < curves; ++c) {
    Curve curve = Keyframes("P" + std::to_string(c), {rng.Unit() * 4.0 - 2.0, rng.Unit()}, {});
    if (rng.OneIn(4)) {
      for (int f = 0; f < frame_count; ++f) curve.samples.push_back(rng.Unit());
    } else {
      double frame = curve.start.frame;
      while (frame < frame_count + 3) {
        const double from = frame;
        frame += rng.OneIn(2) ? rng.Int(1, 12) : 0.3 + 12.0 * rng.Unit();
        CurveSegment segment = Seg(static_cast<SegmentType>(rng.Int(0, 3)), frame, rng.Unit());
        segment.handles[0] = {from + (frame - from) * 0.25 * rng.Unit(), rng.Unit()};
        segment.handles[1] = {frame - (frame - from) * 0.25 * rng.Unit(), rng.Unit()};
        curve.segments.push_back(segment);
      }
    }
    set.curves.push_back(curve);
  }
  return set;
}

KomaUchiOptions RandomOptions(SplitMix64& rng, const CurveSet& set) {
  KomaUchiOptions options;
  options.frames_per_drawing = rng.Int(1, 5);
  options.tame = rng.OneIn(3) ? 1.0 : 1.0 + 3.0 * rng.Unit();
  options.tsume = rng.OneIn(3) ? 1.0 : 1.0 + 3.0 * rng.Unit();
  if (rng.OneIn(2)) {
    for (int f = 0; f < set.frame_count; ++f) {
      if (rng.OneIn(8)) options.key_frames.push_back(f);
    }
  }
  for (const Curve& curve : set.curves) {
    if (rng.OneIn(3)) options.curve_frames_per_drawing[curve.id] = rng.Int(1, 4);
  }
  options.merge_key_poses = rng.OneIn(2);
  const int segments = static_cast<int>(KeyPosesOnGrid(options, set).source.size()) - 1;
  for (int x = 0; x < segments; ++x) {
    if (!rng.OneIn(4)) continue;
    SegmentOverride o;
    o.segment = x;
    if (rng.OneIn(2)) o.frames_per_drawing = rng.Int(1, 4);
    if (rng.OneIn(2)) o.tame = 1.0 + 2.0 * rng.Unit();
    if (rng.OneIn(2)) o.tsume = 1.0 + 2.0 * rng.Unit();
    options.segment_overrides.push_back(o);
  }
  return options;
}

// Invariants of one timing over the key poses.
void ExpectTimingInvariants(const DrawingTiming& timing, const std::vector<int>& keys, int n_max) {
  const int frame_count = keys.back() + 1;
  ASSERT_EQ(static_cast<int>(timing.drawing_of_frame.size()), frame_count);
  ASSERT_EQ(static_cast<int>(timing.source_frame.size()), frame_count);
  for (int f = 1; f < frame_count; ++f) {
    EXPECT_LE(timing.source_frame[f - 1], timing.source_frame[f]) << "frame " << f;
    const int step = timing.drawing_of_frame[f] - timing.drawing_of_frame[f - 1];
    EXPECT_TRUE(step == 0 || step == 1) << "frame " << f;
  }
  for (size_t d = 0; d < timing.drawing_start.size(); ++d) {
    EXPECT_EQ(timing.drawing_of_frame[timing.drawing_start[d]], static_cast<int>(d));
  }
  for (size_t x = 0; x < keys.size(); ++x) {
    EXPECT_EQ(timing.source_frame[keys[x]], keys[x]);  // every key is drawn as itself
    if (keys[x] > 0) {
      EXPECT_NE(timing.drawing_of_frame[keys[x]], timing.drawing_of_frame[keys[x] - 1])
          << "key " << keys[x] << " does not start a drawing";
    }
    // Inside the segment; tau may round to the next key when tsume brings it within an ulp.
    if (x + 1 < keys.size()) {
      for (int f = keys[x]; f < keys[x + 1]; ++f) {
        EXPECT_GE(timing.source_frame[f], keys[x]);
        EXPECT_LE(timing.source_frame[f], keys[x + 1]);
      }
    }
  }
  const std::vector<int> holds = Holds(timing);
  EXPECT_LE(*std::max_element(holds.begin(), holds.end()), n_max);
}

TEST(RetimeCurvesTest, RandomRequestsKeepEveryInvariant) {
  SplitMix64 rng(2019);
  for (int trial = 0; trial < 500; ++trial) {
    SCOPED_TRACE(::testing::Message() << "trial " << trial);
    const CurveSet set = RandomSet(rng);
    const KomaUchiOptions options = RandomOptions(rng, set);
    const KomaUchiResult result = Retime(set, options);
    EXPECT_EQ(result.key_frames, KeyPosesOnGrid(options, set).source);
    if (!MergesKeyPoses(options)) {
      EXPECT_EQ(result.key_frames, KeyPoses(options, set));
    }
    for (const DrawingTiming& timing : result.timings) {
      // Between merged key poses holds are floor(L / n) long: up to 2n - 1 frames.
      ExpectTimingInvariants(timing, result.key_frames, MergesKeyPoses(options) ? 9 : 5);
    }
    ASSERT_EQ(result.curves.size(), set.curves.size());
    for (size_t c = 0; c < set.curves.size(); ++c) {
      const RetimedCurve& out = result.curves[c];
      const DrawingTiming& timing = result.timings[out.timing];
      const auto own = options.curve_frames_per_drawing.find(set.curves[c].id);
      if (own != options.curve_frames_per_drawing.end()) {
        EXPECT_EQ(timing.frames_per_drawing, own->second);
      }
      std::map<int, int> histogram;
      for (int hold : Holds(timing)) ++histogram[hold];
      EXPECT_EQ(out.hold_histogram, histogram);
      ASSERT_EQ(out.steps.size(), timing.drawing_start.size());
      // The curve at its drawing's tau, or a key of the curve a drawing carries (every key is
      // drawn: tests/core/key_drawings_test.cc checks which, exactly).
      for (size_t f = 0; f < out.values.size(); ++f) {
        const bool at_tau = out.values[f] == EvaluateCurve(set.curves[c], timing.source_frame[f],
                                                           set.beziers_restricted);
        const bool a_key = std::any_of(out.keys.begin(), out.keys.end(), [&](const KeyDrawing& k) {
          return k.drawn && k.value == out.values[f];
        });
        ASSERT_TRUE(at_tau || a_key) << "curve " << c << " frame " << f;
      }
    }
  }
}

// The stepped keyframes, evaluated as a motion3 runtime would (stepped segments), give back
// the per-frame values at every integer frame, bit for bit.
TEST(RetimeCurvesTest, SteppedKeyframesReproduceThePerFrameValues) {
  SplitMix64 rng(24);
  for (int trial = 0; trial < 300; ++trial) {
    const CurveSet set = RandomSet(rng);
    const KomaUchiResult result = Retime(set, RandomOptions(rng, set));
    for (const RetimedCurve& out : result.curves) {
      Curve stepped = Keyframes("S", out.steps.front(), {});
      for (size_t k = 1; k < out.steps.size(); ++k) {
        stepped.segments.push_back(
            Seg(SegmentType::kStepped, out.steps[k].frame, out.steps[k].value));
      }
      CurveSet check = SetOf(set.frame_count, {stepped});
      ASSERT_THAT(ValidateCurveSet(check), IsOk());
      for (int f = 0; f < set.frame_count; ++f) {
        ASSERT_EQ(EvaluateCurve(stepped, f, true), out.values[f]) << "trial " << trial;
      }
    }
  }
}

struct InvalidOptions {
  const char* name;
  void (*mutate)(KomaUchiOptions&);
  const char* message;
};

const InvalidOptions kInvalidOptions[] = {
    {"n zero", [](KomaUchiOptions& o) { o.frames_per_drawing = 0; },
     "frames_per_drawing: 0 must be >= 1"},
    {"tame below one", [](KomaUchiOptions& o) { o.tame = 0.5; },
     "tame: 0.5 must be finite and >= 1"},
    {"tsume nan", [](KomaUchiOptions& o) { o.tsume = std::nan(""); }, "tsume: nan"},
    {"tame inf", [](KomaUchiOptions& o) { o.tame = HUGE_VAL; }, "tame: inf"},
    {"key negative",
     [](KomaUchiOptions& o) {
       o.key_frames = {-1, 5};
     },
     "key_frames[0]: -1 is outside [0, 20] (frame_count 21)"},
    {"key past end",
     [](KomaUchiOptions& o) {
       o.key_frames = {5, 21};
     },
     "key_frames[1]: 21 is outside [0, 20]"},
    {"key duplicate",
     [](KomaUchiOptions& o) {
       o.key_frames = {5, 5};
     },
     "key_frames[1]: 5 must be greater than key_frames[0] = 5"},
    {"keys unsorted",
     [](KomaUchiOptions& o) {
       o.key_frames = {0, 9, 4};
     },
     "key_frames[2]: 4 must be greater than key_frames[1] = 9"},
    {"unknown curve",
     [](KomaUchiOptions& o) {
       o.curve_frames_per_drawing = {{"ParamTail", 2}};
     },
     "curve_frames_per_drawing[\"ParamTail\"]: no curve has this id"},
    {"curve n zero",
     [](KomaUchiOptions& o) {
       o.curve_frames_per_drawing = {{"ParamHair", 0}};
     },
     "curve_frames_per_drawing[\"ParamHair\"]: 0 must be >= 1"},
    {"segment out of range",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{0, 2, {}, {}}, {2, {}, {}, {}}};
     },
     "segment_overrides[1].segment: 2 is outside [0, 2) (2 segments between 3 key poses)"},
    {"segment negative",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{-1, {}, {}, {}}};
     },
     "segment_overrides[0].segment: -1 is outside"},
    {"segment twice",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{1, 2, {}, {}}, {1, {}, 2.0, {}}};
     },
     "segment_overrides[1].segment: 1 is already overridden by segment_overrides[0]"},
    {"segment n",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{1, -2, {}, {}}};
     },
     "segment_overrides[0].frames_per_drawing: -2 must be >= 1"},
    {"segment tame",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{0, {}, 0.0, {}}};
     },
     "segment_overrides[0].tame: 0 must be finite and >= 1"},
    {"segment tsume",
     [](KomaUchiOptions& o) {
       o.segment_overrides = {{0, {}, {}, 0.99}};
     },
     "segment_overrides[0].tsume: 0.99 must be finite and >= 1"},
};

TEST(ValidateKomaUchiOptionsTest, RejectsEachBrokenRuleNamingOptionAndValue) {
  const CurveSet set = SetOf(21, {Identity("ParamBody", 21), Identity("ParamHair", 21)});
  KomaUchiOptions valid;
  valid.key_frames = {10};
  valid.curve_frames_per_drawing = {{"ParamHair", 2}};
  valid.segment_overrides = {{1, 2, 1.5, 2.0}};
  ASSERT_THAT(ValidateKomaUchiOptions(valid, set), IsOk());
  for (const InvalidOptions& c : kInvalidOptions) {
    KomaUchiOptions options = valid;
    c.mutate(options);
    EXPECT_THAT(ValidateKomaUchiOptions(options, set),
                StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr(c.message)))
        << c.name;
  }
}

TEST(ValidateKomaUchiOptionsTest, SegmentsCountTheDefaultKeyPoses) {
  // Keyframes at 0, 5, 20 (frame_count 21): two segments, so segment 1 exists, 2 does not.
  const CurveSet set =
      SetOf(21, {Keyframes("A", {0, 0},
                           {Seg(SegmentType::kLinear, 5, 1), Seg(SegmentType::kLinear, 20, 0)})});
  KomaUchiOptions options;
  options.segment_overrides = {{1, 1, {}, {}}};
  EXPECT_THAT(ValidateKomaUchiOptions(options, set), IsOk());
  options.segment_overrides = {{2, 1, {}, {}}};
  EXPECT_THAT(ValidateKomaUchiOptions(options, set),
              StatusIs(absl::StatusCode::kInvalidArgument, HasSubstr("outside [0, 2)")));
}

}  // namespace
}  // namespace koma

// Every key is drawn (docs/semantics.md, "Every key is drawn"): the keys a curve's drawings
// carry, the times they show, against a naive reference of the rule; and the key check on
// generated Cubism-style motions (issue 40's acceptance).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <vector>

#include "core/film_grid.h"
#include "core/key_check.h"
#include "core/key_drawings.h"
#include "core/koma_uchi.h"
#include "core/split_mix64.h"
#include "gtest/gtest.h"
#include "tests/testing/live2d_motion.h"

namespace koma {
namespace {

Curve Linear(std::vector<CurvePoint> points) {
  Curve curve;
  curve.id = "c";
  curve.start = points.front();
  for (size_t i = 1; i < points.size(); ++i) {
    CurveSegment s;
    s.end = points[i];
    curve.segments.push_back(s);
  }
  return curve;
}

std::vector<double> Frames(const std::vector<KeyDrawing>& keys) {
  std::vector<double> frames;
  for (const KeyDrawing& k : keys) frames.push_back(k.frame);
  return frames;
}

TEST(KeysToDrawTest, FirstLastTurnsAndHoldEdges) {
  // 0 -> 5 (turn) -> 2 -> 2 (hold 6..8: both edges) -> 1 -> 0 (monotone: not) -> 3 (last).
  const Curve curve =
      Linear({{0, 0}, {3, 5}, {6, 2}, {8, 2}, {10, 1}, {12, 0}, {15, 3}});
  const std::vector<KeyDrawing> keys = KeysToDraw(curve);
  EXPECT_EQ(Frames(keys), (std::vector<double>{0, 3, 6, 8, 12, 15}));
  EXPECT_EQ(keys.front().role, KeyRole::kFirst);
  EXPECT_EQ(keys.back().role, KeyRole::kLast);
  EXPECT_EQ(keys[1].role, KeyRole::kExtreme);
  EXPECT_EQ(keys[1].swing, 5.0);  // max(|5 - 0|, |2 - 5|)
  // 6: falls in, flat out (a hold starts); 8: flat in, falls out (it ends). 10 falls on both
  // sides; 12 turns (falls, then rises).
}

// Points a reader inserted to shape a curve (a Spine Bezier played as straight pieces) are no
// keys: neither keys to draw (a turn among them is not a keyed extreme) nor key poses.
TEST(KeysToDrawTest, InsertedPointsAreNoKeys) {
  Curve curve = Linear({{0, 0}, {2, 6}, {3, 4}, {10, 10}, {20, 0}});
  curve.segments[0].inserted = true;  // 2 and 3: the played pieces between keys 0 and 10
  curve.segments[1].inserted = true;
  EXPECT_EQ(Frames(KeysToDraw(curve)), (std::vector<double>{0, 10, 20}));
  CurveSet set;
  set.fps = 24.0;
  set.frame_count = 21;
  set.curves = {curve};
  KomaUchiOptions options;
  options.timing_fps = 0.0;
  options.merge_key_poses = false;
  EXPECT_EQ(KeyPoses(options, set), (std::vector<int>{0, 10, 20}));
}

// A dense curve (a CSV's per-frame values): its samples are its keys, so its peak is drawn.
TEST(KeysToDrawTest, ADenseCurvesSamplesAreItsKeys) {
  Curve dense;
  dense.samples = {0, 1, 3, 2, 2, 2, 1};
  EXPECT_EQ(Frames(KeysToDraw(dense)), (std::vector<double>{0, 2, 3, 5, 6}));
}

TEST(KeysToDrawTest, SinglePointAndFlatCurvesHaveNone) {
  Curve point;
  point.start = {0, 1};
  EXPECT_TRUE(KeysToDraw(point).empty());
  EXPECT_TRUE(KeysToDraw(Linear({{0, 2}, {5, 2}, {9, 2}})).empty());  // flat: nothing moves
}

KeyDrawing Key(double frame, double value, KeyRole role, double swing, int drawing) {
  KeyDrawing k;
  k.frame = frame;
  k.value = value;
  k.role = role;
  k.swing = swing;
  k.drawing = drawing;
  return k;
}

TEST(PlaceKeysOnDrawingsTest, CarriesKeysAndNeverStepsBack) {
  // Six drawings with taus 0, 3, 6, 9, 12, 15. A peak keyed at 7.5 falls in drawing 3 (whose
  // tau, 9, is past it): drawing 3 shows 7.5, and drawing 2 (tau 6) stays. A second extreme at
  // 8 of a smaller swing falls in drawing 3 too: it loses it, and is later than the winner, so
  // it moves to drawing 4, where no key falls. The last key at 16 is in drawing 5.
  const std::vector<double> tau = {0, 3, 6, 9, 12, 15};
  const CurveDrawingTimes placed = PlaceKeysOnDrawings(
      {Key(0, 0, KeyRole::kFirst, 1, 0), Key(7.5, 9, KeyRole::kExtreme, 9, 3),
       Key(8, 8, KeyRole::kExtreme, 1, 3), Key(16, 8, KeyRole::kLast, 0, 5)},
      tau);
  EXPECT_EQ(placed.time, (std::vector<double>{0, 3, 6, 7.5, 8, 16}));
  EXPECT_EQ(placed.key, (std::vector<int>{0, -1, -1, 1, 2, 3}));
  EXPECT_TRUE(placed.keys[1].drawn);
  EXPECT_FALSE(placed.keys[1].displaced);
  EXPECT_TRUE(placed.keys[2].drawn);
  EXPECT_TRUE(placed.keys[2].displaced);
  EXPECT_EQ(placed.keys[2].drawing, 4);
  EXPECT_EQ(placed.at_key, (std::vector<int>{0, -1, -1, 1, 2, 3}));
}

TEST(PlaceKeysOnDrawingsTest, AKeyWithNoFreeDrawingBesideIsShared) {
  // Drawing 1 holds keys at 4 (swing 5) and 5 (swing 2); the later loses and would move to
  // drawing 2, but a key falls there: it is not drawn.
  const CurveDrawingTimes placed = PlaceKeysOnDrawings(
      {Key(0, 0, KeyRole::kFirst, 1, 0), Key(4, 5, KeyRole::kExtreme, 5, 1),
       Key(5, 3, KeyRole::kExtreme, 2, 1), Key(7, 5, KeyRole::kExtreme, 2, 2),
       Key(9, 0, KeyRole::kLast, 5, 3)},
      {0, 3, 6, 9});
  EXPECT_EQ(placed.key, (std::vector<int>{0, 1, 3, 4}));
  EXPECT_FALSE(placed.keys[2].drawn);
  EXPECT_EQ(placed.keys[2].drawing, 1);
}

TEST(PlaceKeysOnDrawingsTest, ClampsDrawingsOntoKeysAroundThem) {
  // A key at 2 carried by drawing 0 (tau 0); drawing 1's tau 1 would go back: it shows the key.
  // A key at 10 carried by drawing 3; drawing 2's tau 11 is past it: it shows the key too.
  const std::vector<double> tau = {0, 1, 11, 12};
  const CurveDrawingTimes placed = PlaceKeysOnDrawings(
      {Key(2, 5, KeyRole::kFirst, 1, 0), Key(10, 1, KeyRole::kLast, 1, 3)}, tau);
  EXPECT_EQ(placed.time, (std::vector<double>{2, 2, 10, 10}));
  EXPECT_EQ(placed.at_key, (std::vector<int>{0, 0, 1, 1}));
}

TEST(PlaceKeysOnDrawingsTest, LastAndFirstKeysBeatExtremes) {
  const CurveDrawingTimes placed = PlaceKeysOnDrawings(
      {Key(0, 0, KeyRole::kFirst, 1, 0), Key(1, 9, KeyRole::kExtreme, 9, 0),
       Key(2, 0, KeyRole::kLast, 9, 0)},
      {0.0});
  EXPECT_EQ(placed.key, (std::vector<int>{2}));
  EXPECT_FALSE(placed.keys[0].drawn);
  EXPECT_FALSE(placed.keys[1].drawn);
}

// docs/semantics.md's worked example: a shoulder, the arm trailing it by 2 frames and a hand
// that overshoots and settles, on threes, counted in source frames. The key poses are 0, 12
// (the arm's 14 and the hand's 13 and 14 join it) and 24; drawings start at 0, 3, ..., 21, 24.
TEST(KeyDrawingsTest, WorkedExampleOfStaggeredKeys) {
  CurveSet set;
  set.fps = 24.0;
  set.frame_count = 25;
  Curve shoulder = Linear({{0, 0}, {12, 10}, {24, 0}});
  shoulder.id = "shoulder";
  Curve arm = Linear({{0, 0}, {14, 20}, {24, 0}});
  arm.id = "arm";
  Curve hand = Linear({{0, 0}, {13, 16}, {14, 12}, {24, 12}});
  hand.id = "hand";
  set.curves = {shoulder, arm, hand};
  KomaUchiOptions options;
  options.timing_fps = 0.0;
  const KomaUchiResult result = RetimeCurves(set, options);
  EXPECT_EQ(result.key_frames, (std::vector<int>{0, 12, 24}));
  const auto drawn = [&result](size_t c) {
    std::vector<double> v;
    for (size_t d = 0; d < result.timings[0].drawing_start.size(); ++d) {
      v.push_back(std::round(result.curves[c].steps[d].value * 100) / 100);
    }
    return v;
  };
  EXPECT_EQ(drawn(0), (std::vector<double>{0, 2.5, 5, 7.5, 10, 7.5, 5, 2.5, 0}));
  // The arm's peak (14) is in drawing 4 (frames 12-14): drawn there, not the arm at 12 (17.14).
  EXPECT_EQ(drawn(1), (std::vector<double>{0, 4.29, 8.57, 12.86, 20, 18, 12, 6, 0}));
  // The hand's overshoot (13) wins drawing 4; its settle (14) is later, so drawing 5 shows it.
  EXPECT_EQ(drawn(2), (std::vector<double>{0, 3.69, 7.38, 11.08, 16, 12, 12, 12, 12}));
  EXPECT_TRUE(result.curves[2].keys[2].displaced);
  EXPECT_EQ(result.curves[2].keys[2].drawing, 5);
}

// ---- Property test: RetimeCurves against a naive reference of the rule ----

// A random keyframe curve: staggered keys, linear, Bezier, stepped and inverse-stepped
// segments, holds (equal values), quick accents.
Curve RandomCurve(SplitMix64& rng, const std::string& id, int frame_count) {
  Curve curve;
  curve.id = id;
  double t = rng.Int(0, 6);
  curve.start = {t, std::round(rng.Unit() * 8.0) / 4.0};  // quarter steps: equal values happen
  CurvePoint last = curve.start;
  while (true) {
    t += rng.Unit() < 0.3 ? 1 + rng.Int(0, 1) : rng.Int(2, 12) + (rng.Unit() < 0.3 ? 0.5 : 0.0);
    if (t > frame_count - 1) break;
    CurveSegment s;
    const int kind = rng.Int(0, 9);
    s.type = kind < 4 ? SegmentType::kBezier
             : kind < 8 ? SegmentType::kLinear
             : kind < 9 ? SegmentType::kStepped
                        : SegmentType::kInverseStepped;
    s.end = {t, std::round(rng.Unit() * 8.0) / 4.0};
    if (s.type == SegmentType::kBezier) {
      const double span = t - last.frame;
      s.handles[0] = {last.frame + span * rng.Unit() * 0.5, last.value + rng.Unit() - 0.5};
      s.handles[1] = {t - span * rng.Unit() * 0.5, s.end.value + rng.Unit() - 0.5};
    }
    curve.segments.push_back(s);
    last = s.end;
  }
  if (curve.segments.empty()) {
    CurveSegment s;
    s.end = {static_cast<double>(frame_count - 1), 1.0};
    curve.segments.push_back(s);
  }
  return curve;
}

struct NaiveKey {
  double frame, value, swing;
  int rank;  // 2 last, 1 first, 0 extreme
};

// The rule read literally: the keys, the drawing of each (a linear scan of the drawings'
// starts), the carried key per drawing (a scan of all keys), and per drawing its time (a scan
// for the carried keys around it).
std::vector<double> NaiveValues(const Curve& curve, const DrawingTiming& timing,
                                const std::optional<FilmGrid>& grid, bool restricted,
                                std::vector<int>* carried_out) {
  // The keys: a dense curve's samples, else the start and every segment end.
  std::vector<CurvePoint> p;
  if (curve.dense()) {
    for (size_t f = 0; f < curve.samples.size(); ++f) p.push_back({double(f), curve.samples[f]});
  } else {
    p.push_back(curve.start);
    for (const CurveSegment& s : curve.segments) p.push_back(s.end);
  }
  std::vector<NaiveKey> keys;
  const bool flat = std::all_of(p.begin(), p.end(),
                                [&p](const CurvePoint& q) { return q.value == p[0].value; });
  for (size_t i = 0; i < (flat ? 0 : p.size()); ++i) {
    const double in = i > 0 ? p[i].value - p[i - 1].value : 0;
    const double out = i + 1 < p.size() ? p[i + 1].value - p[i].value : 0;
    const int rank = i + 1 == p.size() ? 2 : i == 0 ? 1 : 0;
    const bool extreme = (in * out < 0) || ((in == 0) != (out == 0));
    // The value shown at the key: an inverse-stepped segment shows the next point's from there.
    const double shown = !curve.dense() && i + 1 < p.size() &&
                                 curve.segments[i].type == SegmentType::kInverseStepped
                             ? p[i + 1].value
                             : p[i].value;
    if (rank > 0 || extreme) keys.push_back({p[i].frame, shown, std::max(std::fabs(in), std::fabs(out)), rank});
  }
  const size_t drawings = timing.drawing_start.size();
  std::vector<double> tau(drawings);
  for (size_t d = 0; d < drawings; ++d) {
    tau[d] = grid ? timing.drawing_tau[d] : timing.source_frame[timing.drawing_start[d]];
  }
  const auto drawing_of = [&](double frame) {
    int unit;  // the frame the key snaps to on the timing's frames
    if (grid) {
      unit = 0;  // nearest grid frame, ties to the earlier
      for (int g = 0; g <= timing.drawing_start_grid.back(); ++g) {
        if (std::fabs(grid->SourceTime(g) - frame) < std::fabs(grid->SourceTime(unit) - frame)) {
          unit = g;
        }
      }
    } else {
      unit = static_cast<int>(std::clamp(std::round(frame), 0.0,
                                         static_cast<double>(timing.drawing_of_frame.size() - 1)));
    }
    const std::vector<int>& starts = grid ? timing.drawing_start_grid : timing.drawing_start;
    int d = 0;
    for (size_t k = 0; k < drawings; ++k) {
      if (starts[k] <= unit) d = static_cast<int>(k);
    }
    return d;
  };
  const auto beats = [&keys](size_t k, int c) {
    return c < 0 || keys[k].rank > keys[c].rank ||
           (keys[k].rank == keys[c].rank && keys[k].swing > keys[c].swing);
  };
  std::vector<int> carried(drawings, -1);
  std::vector<int> home(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) {
    home[k] = drawing_of(keys[k].frame);
    if (beats(k, carried[home[k]])) carried[home[k]] = static_cast<int>(k);
  }
  // Losers move next door, to the side of the winner they are on, where no key fell.
  std::vector<int> moved = carried;
  for (size_t k = 0; k < keys.size(); ++k) {
    const int winner = carried[home[k]];
    if (winner == static_cast<int>(k)) continue;
    const int target = keys[k].frame < keys[winner].frame ? home[k] - 1 : home[k] + 1;
    if (target < 0 || target >= static_cast<int>(drawings) || carried[target] >= 0) continue;
    if (moved[target] < 0 || beats(k, moved[target])) moved[target] = static_cast<int>(k);
  }
  carried = moved;
  std::vector<double> values(drawings);
  for (size_t d = 0; d < drawings; ++d) {
    if (carried[d] >= 0) {
      values[d] = keys[carried[d]].value;
      continue;
    }
    int before = -1, after = -1;
    for (size_t e = 0; e < d; ++e) {
      if (carried[e] >= 0) before = carried[e];
    }
    for (size_t e = drawings; e-- > d + 1;) {
      if (carried[e] >= 0) after = carried[e];
    }
    if (before >= 0 && tau[d] <= keys[before].frame) {
      values[d] = keys[before].value;
    } else if (after >= 0 && tau[d] >= keys[after].frame) {
      values[d] = keys[after].value;
    } else {
      values[d] = EvaluateCurve(curve, tau[d], restricted);
    }
  }
  if (carried_out != nullptr) *carried_out = carried;
  return values;
}

TEST(KeyDrawingsPropertyTest, RetimeCurvesMatchesTheNaiveRule) {
  SplitMix64 rng(40);
  int checked_drawings = 0, carried_keys = 0;
  for (int round = 0; round < 300; ++round) {
    CurveSet set;
    set.fps = rng.Unit() < 0.5 ? 30.0 : (rng.Unit() < 0.5 ? 60.0 : 24.0);
    set.frame_count = rng.Int(20, 160);
    set.beziers_restricted = rng.Unit() < 0.5;
    const int curves = rng.Int(1, 6);
    for (int c = 0; c < curves; ++c) {
      set.curves.push_back(RandomCurve(rng, "c" + std::to_string(c), set.frame_count));
      if (rng.Int(0, 7) == 0) {  // a CSV's curve: a sample per frame, quarter steps
        Curve& dense = set.curves.back();
        dense.samples.resize(static_cast<size_t>(set.frame_count));
        for (double& v : dense.samples) v = std::round(rng.Unit() * 8.0) / 4.0;
      }
    }
    ASSERT_TRUE(ValidateCurveSet(set).ok()) << round;
    KomaUchiOptions options;
    options.frames_per_drawing = rng.Int(1, 4);
    options.tame = 1.0 + rng.Unit() * 2.0;
    options.tsume = 1.0 + rng.Unit() * 2.0;
    options.timing_fps = rng.Unit() < 0.7 ? 24.0 : 0.0;
    options.merge_key_poses = rng.Unit() < 0.8;
    ASSERT_TRUE(ValidateKomaUchiOptions(options, set).ok()) << round;
    const KomaUchiResult result = RetimeCurves(set, options);
    const std::optional<FilmGrid> grid = FilmGrid::Make(set.fps, options.timing_fps);
    for (size_t c = 0; c < set.curves.size(); ++c) {
      const DrawingTiming& timing = result.timings[result.curves[c].timing];
      std::vector<int> carried;
      const std::vector<double> want =
          NaiveValues(set.curves[c], timing, grid, set.beziers_restricted, &carried);
      const RetimedCurve& got = result.curves[c];
      ASSERT_GE(got.steps.size(), want.size());
      for (size_t d = 0; d < want.size(); ++d) {
        // Bit for bit: the same evaluation at the same times.
        ASSERT_EQ(got.steps[d].value, want[d]) << "round " << round << " curve " << c
                                               << " drawing " << d;
        ++checked_drawings;
        if (carried[d] >= 0) ++carried_keys;
      }
      // Every key the answer lists as drawn is shown by its drawing, exactly.
      for (const KeyDrawing& key : got.keys) {
        if (key.drawn) {
          ASSERT_EQ(got.steps[key.drawing].value, key.value) << round;
        }
      }
    }
  }
  EXPECT_GT(checked_drawings, 10000);
  EXPECT_GT(carried_keys, 1000);
}

// No backward step: per curve, the source times its drawings show never decrease. Checked on
// monotone curves, where a value going back means a time going back.
TEST(KeyDrawingsPropertyTest, DrawingsNeverStepBackBetweenKeys) {
  SplitMix64 rng(41);
  for (int round = 0; round < 200; ++round) {
    CurveSet set;
    set.fps = 30.0;
    set.frame_count = rng.Int(30, 120);
    Curve curve;
    curve.id = "rise";
    double t = 0, v = 0;
    curve.start = {t, v};
    while (true) {
      t += rng.Int(1, 9);
      if (t > set.frame_count - 1) break;
      v += rng.Unit();  // strictly rising: the only extremes are the first and last keys
      CurveSegment s;
      s.type = SegmentType::kLinear;
      s.end = {t, v};
      curve.segments.push_back(s);
    }
    if (curve.segments.empty()) continue;
    set.curves.push_back(curve);
    KomaUchiOptions options;
    options.frames_per_drawing = rng.Int(2, 3);
    options.tame = options.tsume = 1.0 + rng.Unit() * 2.0;
    options.timing_fps = 24.0;
    const KomaUchiResult result = RetimeCurves(set, options);
    const std::vector<CurvePoint>& steps = result.curves[0].steps;
    for (size_t d = 1; d < steps.size(); ++d) {
      ASSERT_GE(steps[d].value, steps[d - 1].value) << "round " << round << " drawing " << d;
    }
    EXPECT_EQ(steps.back().value, curve.segments.back().end.value);
    EXPECT_EQ(steps.front().value, curve.start.value);
  }
}

// A key pose snapped to the grid shows the curves at the key's own time: a 30 fps curve keyed
// at frame 8 (0.2667 s) snaps to grid frame 6 (0.25 s), and its drawing shows the key's value,
// not the curve at 0.25 s. The same for the clip's last key.
TEST(KeyDrawingsTest, KeyPoseOnTheGridShowsTheKeysOwnTime) {
  CurveSet set;
  set.fps = 30.0;
  set.frame_count = 31;
  Curve curve;
  curve.id = "torso";
  curve.start = {0, 0};
  for (const CurvePoint& p : std::vector<CurvePoint>{{8, 30}, {16, 0}, {24, 30}, {30, 0}}) {
    CurveSegment s;
    s.type = SegmentType::kBezier;
    s.handles[0] = {p.frame - 4, 10};
    s.handles[1] = {p.frame - 1, p.value};
    s.end = p;
    curve.segments.push_back(s);
  }
  set.curves.push_back(curve);
  KomaUchiOptions options;
  options.timing_fps = 24.0;
  const KomaUchiResult result = RetimeCurves(set, options);
  const RetimedCurve& out = result.curves[0];
  std::vector<double> drawn;
  for (const CurvePoint& step : out.steps) drawn.push_back(step.value);
  for (double key : {0.0, 30.0}) {
    EXPECT_NE(std::find(drawn.begin(), drawn.end(), key), drawn.end()) << key;
  }
  EXPECT_EQ(out.steps.back().value, 0.0);   // the cycle's last key: the loop closes
  EXPECT_EQ(out.steps.front().value, 0.0);
  for (const KeyDrawing& key : out.keys) EXPECT_TRUE(key.drawn) << key.frame;
  EXPECT_EQ(out.keys.size(), 5u);
}

// The check itself: a peak drawn a quarter of its swing short is missed, the same peak drawn
// exactly is not; an end drawn off its key is counted.
TEST(KeyCheckTest, CountsMissedExtremesAndEnds) {
  CurveSet set;
  set.fps = 24.0;
  set.frame_count = 13;
  set.curves.push_back(Linear({{0, 0}, {6, 8}, {12, 0}}));
  const std::vector<CurvePoint> exact = {{0, 0}, {3, 4}, {6, 8}, {9, 4}, {12, 0}};
  const std::vector<CurvePoint> short_peak = {{0, 0}, {3, 4}, {6, 6}, {9, 4}, {12, 1}};
  KeyCheck good = CheckKeys(set, {&exact}, {0.0, 3, 0.005});
  EXPECT_EQ(good.extremes, 1);
  EXPECT_EQ(good.extremes_missed, 0);
  EXPECT_EQ(good.ends_missed, 0);
  EXPECT_EQ(good.curves[0].drawings, 5);
  KeyCheck bad = CheckKeys(set, {&short_peak}, {0.0, 3, 0.005});
  EXPECT_EQ(bad.extremes_missed, 1);
  EXPECT_DOUBLE_EQ(bad.curves[0].worst_miss, 0.25);
  EXPECT_EQ(bad.ends_missed, 1);
  EXPECT_TRUE(bad.curves[0].last_missed);
}

// ---- The acceptance measure on generated Cubism-style motions ----

TEST(KeyDrawingsAcceptanceTest, GeneratedMotionsKeepEveryKeyedExtreme) {
  for (int n : {3, 2}) {
    int extremes = 0, missed = 0, shared = 0, ends_missed = 0;
    std::vector<double> rates;
    for (uint64_t seed = 1; seed <= 12; ++seed) {
      for (double fps : {30.0, 60.0}) {
        testing::Live2dMotionSpec spec{fps, 40 + static_cast<int>((seed * 7) % 41),
                                       4.0 + seed % 4, seed};
        spec.accents = true;
        spec.loops = seed % 2 == 0;
        const CurveSet set = testing::Live2dMotion(spec);
        KomaUchiOptions options;
        options.frames_per_drawing = n;
        options.timing_fps = 24.0;
        ASSERT_TRUE(ValidateKomaUchiOptions(options, set).ok());
        const KomaUchiResult result = RetimeCurves(set, options);
        std::vector<const std::vector<CurvePoint>*> stepped;
        for (const RetimedCurve& c : result.curves) stepped.push_back(&c.steps);
        const KeyCheck check = CheckKeys(set, stepped, {24.0, 3, 0.005});
        extremes += check.extremes;
        missed += check.extremes_missed;
        ends_missed += check.ends_missed;
        int motion_shared = 0;
        for (const RetimedCurve& c : result.curves) {
          for (const KeyDrawing& k : c.keys) motion_shared += k.drawn ? 0 : 1;
        }
        shared += motion_shared;
        // A miss only where two keys shared a drawing (and the server counted it).
        EXPECT_LE(check.extremes_missed, motion_shared) << "seed " << seed << " fps " << fps;
        for (const CurveKeyCheck& c : check.curves) rates.push_back(c.drawings / check.seconds);
      }
    }
    std::sort(rates.begin(), rates.end());
    const double p95 = rates[static_cast<size_t>(std::ceil(0.95 * rates.size())) - 1];
    std::ostringstream figures;
    figures << "on " << n << "s: " << extremes << " keyed extremes, " << missed
            << " missed by > 0.5% (" << shared << " keys shared a drawing), " << ends_missed
            << " ends missed; drawings a second p95 " << p95 << ", max " << rates.back();
    std::cout << figures.str() << "\n";
    ::testing::Test::RecordProperty("on_" + std::to_string(n) + "s", figures.str());
    EXPECT_GT(extremes, 5000);
    EXPECT_EQ(ends_missed, 0);
    EXPECT_LE(p95, n == 3 ? 8.5 : 12.5);
  }
}

}  // namespace
}  // namespace koma

// LipBlink on the film grid (docs/semantics.md, "The film grid", issue 17), on 500 random requests
// per source rate (25 .. 240 fps and 29.97; 12, 15 and 23.976, slower than the grid; and on other
// grids, where "24" below reads as the grid's rate: 60 on 30, 50 and 30 on 12, 24 on 8):
// converting at rate R (timing_fps unset: 24) equals
// converting the curves sampled at the grid's times as a 24 fps clip with no grid (timing_fps
// 0; speech and keep intervals at their nearest grid frames): the same speech, mouth holds,
// blinks and levels, and per source frame k, with g = floor(k * 24 / R), the 24 fps answer's
// value of grid frame g where g is repainted (inside speech, or from a blink's closing_begin
// to the end of its repaint) or is the grid frame just before a repainted run, else the input
// at frame k. The stepped keys give back those per-frame values at every source frame, each
// on a source frame or at an exact grid time.
//
// Grid times in source frames are g * p / q with the grid's ratio p / q (core/film_grid.h;
// 246 / 197 for 29.97, exact otherwise); floor(k * 24 / R) may be either neighbour where it
// lies within that ratio's error of a boundary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/split_mix64.h"
#include "koma/v1/retime.pb.h"
#include "server/curve_convert.h"
#include "server/lip_blink_request.h"
#include "server/request_limits.h"
#include "tests/testing/grid_rates.h"

namespace koma::server {
namespace {

constexpr int kRequestsPerRate = 500;

using Rate = ::koma::testing::GridRate;
using ::koma::testing::GridFramesOf;
using ::koma::testing::NearestGridFrame;

// Disjoint sorted intervals within [0, frames]: some long, some a frame or two (which may
// vanish on the grid).
void RandomIntervals(SplitMix64& rng, int frames, int scale,
                     google::protobuf::RepeatedPtrField<v1::FrameInterval>* out) {
  int at = rng.Int(0, std::max(1, frames / 4));
  while (at < frames && out->size() < 6) {
    const int length = rng.OneIn(3) ? rng.Int(1, 2) : rng.Int(1, 12 * scale);
    const int end = std::min(frames, at + length);
    v1::FrameInterval* i = out->Add();
    i->set_begin(at);
    i->set_end(end);
    at = end + rng.Int(0, 10 * scale);
  }
}

// A mouth curve: silence and talking stretches, dense or as keyframes.
void RandomMouth(SplitMix64& rng, int frames, int scale, v1::Curve* curve) {
  curve->set_id("ParamMouthOpenY");
  if (rng.OneIn(3)) {
    double t = 0;
    curve->mutable_start()->set_frame(0);
    curve->mutable_start()->set_value(0);
    while (t < frames - 1) {
      const double next = t + 0.5 + rng.Unit() * 4 * scale;
      v1::CurveSegment* s = curve->add_segments();
      s->set_type(rng.OneIn(3) ? v1::SEGMENT_STEPPED : v1::SEGMENT_LINEAR);
      s->mutable_end()->set_frame(next);
      s->mutable_end()->set_value(rng.OneIn(3) ? 0.0 : rng.Unit());
      t = next;
    }
    return;
  }
  bool talking = rng.OneIn(2);
  int left = 0;
  double v = 0;
  for (int k = 0; k < frames; ++k) {
    if (left-- <= 0) {
      talking = !talking;
      left = rng.Int(1, 20 * scale);
    }
    if (talking) v = rng.Unit();
    curve->add_samples(v);
  }
}

// An eye curve: open (1) with blinks that close over a few frames, stay shut, and reopen;
// `blinks` are the shared blink times (the other eye a frame or so off).
void RandomEye(SplitMix64& rng, int frames, int scale, const std::vector<int>& blinks,
               const std::string& id, v1::Curve* curve) {
  curve->set_id(id);
  std::vector<double> v(static_cast<size_t>(frames), 1.0);
  for (int b : blinks) {
    int k = b + rng.Int(0, 1);
    const int closing = rng.Int(0, 2 * scale), shut = rng.Int(1, 3 * scale),
              opening = rng.Int(0, 4 * scale);
    for (int i = 1; i <= closing && k < frames; ++i, ++k) v[k] = 1.0 - i / (closing + 1.0);
    for (int i = 0; i < shut && k < frames; ++i, ++k) v[k] = rng.OneIn(4) ? 0.05 : 0.0;
    for (int i = 1; i <= opening && k < frames; ++i, ++k) v[k] = i / (opening + 1.0);
  }
  if (rng.OneIn(4)) {  // as keyframes: a polyline through every 1 .. 3rd sample
    curve->mutable_start()->set_frame(0);
    curve->mutable_start()->set_value(v[0]);
    for (int k = rng.Int(1, 3); k < frames; k += rng.Int(1, 3)) {
      v1::CurveSegment* s = curve->add_segments();
      s->set_type(v1::SEGMENT_LINEAR);
      s->mutable_end()->set_frame(k);
      s->mutable_end()->set_value(v[k]);
    }
    return;
  }
  for (double x : v) curve->add_samples(x);
}

struct Pair {
  v1::LipBlinkRequest at_rate;  // the clip at R, on the default grid
  v1::LipBlinkRequest at_24;    // its curves sampled at the grid's times, 24 fps, no grid
  int grid_frames = 0;
};

Pair RandomPair(SplitMix64& rng, const Rate& r) {
  Pair pair;
  // Source frames n with floor((n - 1) q / p) = g - 1 (below 24 fps not every g has one).
  int64_t lo = 0, hi = -1;
  while (hi < lo) {
    pair.grid_frames = rng.Int(2, 150);
    lo = ((pair.grid_frames - 1) * r.p + r.q - 1) / r.q;
    hi = (pair.grid_frames * r.p + r.q - 1) / r.q - 1;
  }
  const int g = pair.grid_frames;
  const int n = static_cast<int>(lo + rng.Int(0, static_cast<int>(hi - lo))) + 1;
  const int scale = static_cast<int>(std::max<int64_t>(1, (r.num / r.den + 12) / 24));
  v1::LipBlinkRequest& req = pair.at_rate;
  v1::CurveSet* set = req.mutable_curves();
  set->set_fps(r.fps());
  set->set_frame_count(n);
  set->set_beziers_restricted(rng.OneIn(2));
  if (!rng.OneIn(5)) RandomMouth(rng, n, scale, set->add_curves());
  std::vector<int> blinks;
  for (int k = rng.Int(0, 10 * scale); k < n; k += rng.Int(8 * scale, 40 * scale)) {
    blinks.push_back(k);
  }
  const int eyes = set->curves_size() == 0 ? rng.Int(1, 2) : rng.Int(0, 2);
  for (int e = 0; e < eyes; ++e) {
    RandomEye(rng, n, scale, blinks, e == 0 ? "ParamEyeLOpen" : "ParamEyeROpen",
              set->add_curves());
  }
  v1::MouthSettings* mouth = req.mutable_mouth();
  if (rng.OneIn(2)) mouth->set_frames_per_shape(rng.Int(1, 4));
  mouth->set_mode(rng.OneIn(2) ? v1::MOUTH_FOLLOW : v1::MOUTH_RANDOM);
  if (rng.OneIn(3)) mouth->set_mid_ratio(0.1 + 0.8 * rng.Unit());
  if (rng.OneIn(3)) RandomIntervals(rng, n, scale, mouth->mutable_speech());
  v1::EyeSettings* eye = req.mutable_eyes();
  if (rng.OneIn(3)) eye->set_threshold(0.05 + 0.2 * rng.Unit());
  if (rng.OneIn(3)) eye->set_mid_ratio(0.1 + 0.8 * rng.Unit());
  if (rng.OneIn(3)) eye->set_linked(false);
  if (rng.OneIn(4)) {
    v1::AutoBlink* a = eye->mutable_auto_blink();
    a->set_enabled(true);
    a->set_mean_interval_s(0.5 + 1.5 * rng.Unit());
    if (rng.OneIn(2)) a->set_hold(rng.Int(1, 3));
    if (rng.OneIn(2)) RandomIntervals(rng, n, scale, a->mutable_keep());
  }
  req.set_seed(rng.Next());
  if (r.t != 24) req.set_timing_fps(static_cast<double>(r.t));

  // The 24 fps version: the same settings, intervals snapped, curves sampled on the grid.
  pair.at_24 = req;
  pair.at_24.set_timing_fps(0.0);
  v1::CurveSet* set24 = pair.at_24.mutable_curves();
  set24->set_fps(static_cast<double>(r.t));
  set24->set_frame_count(g);
  const absl::StatusOr<CurveSet> core = CurveSetFromProto(*set, "curves", RequestLimits{});
  EXPECT_TRUE(core.ok()) << core.status();
  for (int c = 0; c < set->curves_size(); ++c) {
    v1::Curve* out = set24->mutable_curves(c);
    out->clear_start();
    out->clear_segments();
    out->clear_samples();
    for (int f = 0; f < g; ++f) {
      out->add_samples(EvaluateCurve(core->curves[c], r.SourceTime(f), set->beziers_restricted()));
    }
  }
  const auto snap = [&r, g](google::protobuf::RepeatedPtrField<v1::FrameInterval>* in) {
    google::protobuf::RepeatedPtrField<v1::FrameInterval> out;
    for (const v1::FrameInterval& i : *in) {
      const int b = std::min(NearestGridFrame(r, i.begin()), g);
      const int e = std::min(NearestGridFrame(r, i.end()), g);
      if (e <= b) continue;
      v1::FrameInterval* o = out.Add();
      o->set_begin(b);
      o->set_end(e);
    }
    in->Swap(&out);
  };
  snap(pair.at_24.mutable_mouth()->mutable_speech());
  snap(pair.at_24.mutable_eyes()->mutable_auto_blink()->mutable_keep());
  return pair;
}

// Grid frames repainted for one curve of the 24 fps answer: its mouth's speech, or its eye's
// blinks from closing_begin through the repaint's end (docs/semantics.md, "LipBlink": closed
// through max(C_end, C_start + k - 1), then k half-open frames, the opening span, never into the
// next blink or past the clip); then the grid frame just before each repainted run.
std::vector<bool> Repainted(const v1::LipBlinkResponse& at_24, const std::string& id, int g) {
  std::vector<bool> mask(static_cast<size_t>(g), false);
  for (const v1::MouthTrack& m : at_24.mouths()) {
    if (m.id() != id) continue;
    for (const v1::FrameInterval& i : m.speech()) {
      for (int f = i.begin(); f < i.end(); ++f) mask[f] = true;
    }
  }
  for (const v1::EyeTrack& e : at_24.eyes()) {
    if (e.id() != id) continue;
    for (int i = 0; i < e.blinks_size(); ++i) {
      const v1::Blink& b = e.blinks(i);
      const int closed_last = std::max(b.closed_end(), b.closed_begin() + b.hold() - 1);
      const int limit = i + 1 < e.blinks_size() ? e.blinks(i + 1).closing_begin() : g;
      const int end =
          std::min(limit, std::max(b.closed_end() + 1 + b.open_span(), closed_last + 1 + b.hold()));
      for (int f = b.closing_begin(); f < end; ++f) mask[f] = true;
    }
  }
  std::vector<bool> out = mask;
  for (int f = 0; f + 1 < g; ++f) {
    if (mask[f + 1]) out[f] = true;
  }
  return out;
}

// "" or what differs.
std::string Compare(const Rate& r, const Pair& pair, const v1::LipBlinkResponse& got,
                    const v1::LipBlinkResponse& want) {
  std::ostringstream why;
  if (got.timing_fps() != static_cast<double>(r.t)) return "timing_fps " + std::to_string(got.timing_fps());
  if (want.timing_fps() != 0.0) return "the 24 fps answer has a grid";
  if (got.seed() != want.seed()) return "seed";
  if (got.mouths_size() != want.mouths_size() || got.eyes_size() != want.eyes_size()) {
    return "track counts";
  }
  for (int m = 0; m < got.mouths_size(); ++m) {
    if (got.mouths(m).SerializeAsString() != want.mouths(m).SerializeAsString()) {
      return "mouths[" + std::to_string(m) + "]: " + got.mouths(m).ShortDebugString() +
             "\n want " + want.mouths(m).ShortDebugString();
    }
  }
  for (int e = 0; e < got.eyes_size(); ++e) {
    if (got.eyes(e).SerializeAsString() != want.eyes(e).SerializeAsString()) {
      return "eyes[" + std::to_string(e) + "]: " + got.eyes(e).ShortDebugString() +
             "\n want " + want.eyes(e).ShortDebugString();
    }
  }
  if (got.curves_size() != want.curves_size()) return "curve count";
  const v1::CurveSet& set = pair.at_rate.curves();
  const absl::StatusOr<CurveSet> core = CurveSetFromProto(set, "curves", RequestLimits{});
  const int n = set.frame_count(), g = pair.grid_frames;
  for (int c = 0; c < got.curves_size(); ++c) {
    const v1::ConvertedCurve& gc = got.curves(c);
    const v1::ConvertedCurve& wc = want.curves(c);
    if (gc.id() != wc.id()) return "curve ids";
    if (gc.values_size() != n || wc.values_size() != g) return "value counts of " + gc.id();
    const Curve* input = nullptr;
    for (const Curve& in : core->curves) {
      if (in.id == gc.id()) input = &in;
    }
    const std::vector<bool> repainted = Repainted(want, gc.id(), g);
    for (int k = 0; k < n; ++k) {
      const double source = EvaluateCurve(*input, k, set.beziers_restricted());
      bool ok = false;
      std::ostringstream options;
      for (int f : GridFramesOf(r, k, g - 1)) {
        const double expected = repainted[f] ? wc.values(f) : source;
        ok = ok || gc.values(k) == expected;
        options << " " << expected << (repainted[f] ? " (grid frame " : " (input, grid frame ")
                << f << ")";
      }
      if (!ok) {
        why << gc.id() << " frame " << k << ": " << gc.values(k) << ", want" << options.str();
        return why.str();
      }
    }
    // The stepped keys give back every frame's value; each lies on a source frame or a grid time.
    const v1::Curve& stepped = gc.stepped();
    Curve steps;
    steps.id = "s";
    steps.start = {stepped.start().frame(), stepped.start().value()};
    std::vector<double> times = {steps.start.frame};
    for (const v1::CurveSegment& s : stepped.segments()) {
      if (s.type() != v1::SEGMENT_STEPPED) return gc.id() + ": a segment is not stepped";
      CurveSegment seg;
      seg.type = SegmentType::kStepped;
      seg.end = {s.end().frame(), s.end().value()};
      steps.segments.push_back(seg);
      times.push_back(s.end().frame());
    }
    for (int k = 0; k < n; ++k) {
      if (EvaluateCurve(steps, k, false) != gc.values(k)) {
        return gc.id() + ": the stepped keys at frame " + std::to_string(k) + " give " +
               std::to_string(EvaluateCurve(steps, k, false)) + ", values " +
               std::to_string(gc.values(k));
      }
    }
    for (double t : times) {
      const double grid = std::round(t * static_cast<double>(r.q) / static_cast<double>(r.p));
      if (t != std::round(t) && t != r.SourceTime(grid)) {
        return gc.id() + ": a step at " + std::to_string(t) + " is on no frame";
      }
    }
  }
  return "";
}

class LipBlinkGridPropertyTest : public ::testing::TestWithParam<Rate> {};

TEST_P(LipBlinkGridPropertyTest, ConvertingAtRateEqualsConvertingTheGridSamplesExpanded) {
  const Rate r = GetParam();
  ASSERT_LE(r.ratio_error(), 1e-4);
  int failures = 0;
  int with_speech = 0, with_blinks = 0, vanished = 0;
  for (uint64_t seed = 1; seed <= kRequestsPerRate && failures < 3; ++seed) {
    SplitMix64 rng(seed * 1000003 + static_cast<uint64_t>(r.num));
    const Pair pair = RandomPair(rng, r);
    if (pair.at_rate.mouth().speech_size() > 0 && pair.at_24.mouth().speech_size() == 0) {
      // Every given interval vanished: the grid answer has no speech, which a 24 fps request
      // cannot ask for (no intervals there means "detect"). GridBadRequestTableTest.
      // SpeechThatVanishesOnTheGridDoesNotCrash checks that case.
      continue;
    }
    const std::string context = "seed " + std::to_string(seed) + ", " +
                                std::to_string(pair.at_rate.curves().frame_count()) +
                                " frames at " + std::to_string(r.fps()) + " fps";
    v1::LipBlinkResponse got, want;
    const absl::Status got_status = HandleLipBlink(pair.at_rate, RequestLimits{}, &got);
    const absl::Status want_status = HandleLipBlink(pair.at_24, RequestLimits{}, &want);
    ASSERT_TRUE(want_status.ok()) << context << ": " << want_status;
    ASSERT_TRUE(got_status.ok()) << context << ": " << got_status;
    const std::string why = Compare(r, pair, got, want);
    if (!why.empty()) {
      ++failures;
      ADD_FAILURE() << context << ": " << why;
    }
    for (const v1::MouthTrack& m : want.mouths()) with_speech += m.speech_size() > 0;
    for (const v1::EyeTrack& e : want.eyes()) with_blinks += e.blinks_size() > 0;
    vanished += pair.at_24.mouth().speech_size() < pair.at_rate.mouth().speech_size();
  }
  // The draws do exercise what they are meant to.
  EXPECT_GT(with_speech, kRequestsPerRate / 4);
  EXPECT_GT(with_blinks, kRequestsPerRate / 4);
  if (r.p >= 2 * r.q) {
    EXPECT_GT(vanished, 0) << "no speech interval vanished on the grid";
  }
}

INSTANTIATE_TEST_SUITE_P(Rates, LipBlinkGridPropertyTest,
                         ::testing::ValuesIn(::koma::testing::GridRates()),
                         ::koma::testing::GridRateName());

}  // namespace
}  // namespace koma::server

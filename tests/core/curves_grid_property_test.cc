// RetimeCurves on the film grid (docs/semantics.md, "The film grid", issue 17), on 500 random clips
// per source rate (25 .. 240 fps and 29.97; and 12, 15 and 23.976, slower than the grid; and
// grids other than 24: 60 on 30, 50 and 30 on 12, 24 on 8, 25 on 1000, where "24" below
// reads as that grid's rate):
//  - retiming at rate R with timing_fps 24 equals retiming the same curves expressed at 24 fps
//    (keyframe times in 24 fps frames, frame_count = the grid's frame count, key poses at their
//    nearest 24 fps frame) with no grid, expanded back to R by the rule written here: source
//    frame k shows the drawing of grid frame floor(k * 24 / R); a drawing's tau lies at the
//    same fraction of its segment, between the key poses' own source times (docs/semantics.md:
//    a key pose snapped to the grid shows its own time), and each curve shows its tau or one
//    of its keys (which one: tests/core/key_drawings_test.cc, against a naive reference);
//  - on a 30 fps motion with only its first and last key pose, on threes, every 1-second
//    stretch shows exactly 8 drawings, and the stepped keys lie on multiples of 1/24 s;
//  - no drawing is shown for less than one grid frame (but the last key pose's, which the
//    clip's end cuts) nor for more than n grid frames, in seconds, and the stepped keys give
//    back the per-frame values at every source frame.
//
// The grid's ratio of rates is a fraction p / q within 1e-4 of R / 24 (core/film_grid.h; exact
// for integer rates, 246 / 197 for 29.97): the clip's times are converted with it, and the
// expansion rule allows either grid frame where k * 24 / R lies that close to a grid frame's
// boundary. The curves are drawn in 24 fps frames and mapped to source frames (t * p / q, the
// grid's own monotone arithmetic), so a stepped segment's jump sits on the same side of a
// drawing's tau in both runs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/film_grid.h"
#include "core/koma_uchi.h"
#include "core/split_mix64.h"
#include "tests/testing/grid_rates.h"
#include "tests/testing/status_matchers.h"

namespace koma {
namespace {

using ::koma::testing::IsOk;

constexpr int kClipsPerRate = 500;

using Rate = ::koma::testing::GridRate;
using ::koma::testing::GridFramesOf;
using ::koma::testing::NearestGridFrame;

// The shared rates, and a grid finer than the source: 25 fps on 1000.
std::vector<Rate> Rates() {
  std::vector<Rate> rates = ::koma::testing::GridRates();
  rates.push_back({25, 1, 1, 40, 1000});
  return rates;
}

// Grid frames at or before the last source frame (n - 1) * q / p.
int RefGridCount(const Rate& r, int n) { return static_cast<int>(((n - 1) * r.q) / r.p) + 1; }

bool Near(double got, double want, double rel = 1e-9) {
  return std::fabs(got - want) <= rel * std::max(1.0, std::fabs(want));
}

// A random clip: the curves at the source rate and the same curves at 24 fps, with options
// for both (the reference's key poses are the source's snapped to the grid by the rule).
struct Clip {
  CurveSet source;
  CurveSet reference;
  KomaUchiOptions options;
  KomaUchiOptions ref_options;
  int grid_frames = 0;
};

// A keyframe curve drawn in grid frames; `to_source` maps its times to source frames.
template <typename ToSource>
void RandomKeyframes(SplitMix64& rng, int grid_frames, ToSource to_source, Curve* grid_curve,
                     Curve* source_curve) {
  const auto value = [&rng] { return rng.OneIn(6) ? 0.0 : rng.Unit() * 60.0 - 30.0; };
  double t = rng.OneIn(3) ? rng.Unit() : 0.0;
  grid_curve->start = {t, value()};
  while (t < grid_frames - 1) {
    const double next = t + (rng.OneIn(2) ? rng.Int(1, 8) : 0.2 + rng.Unit() * 8.0);
    CurveSegment segment;
    segment.type = static_cast<SegmentType>(rng.Int(0, 3));
    if (segment.type == SegmentType::kBezier) {
      double a = rng.Unit(), b = rng.Unit();
      if (a > b) std::swap(a, b);
      segment.handles[0] = {t + a * (next - t), rng.Unit() * 60.0 - 30.0};
      segment.handles[1] = {t + b * (next - t), rng.Unit() * 60.0 - 30.0};
    }
    segment.end = {next, value()};
    grid_curve->segments.push_back(segment);
    t = next;
  }
  *source_curve = *grid_curve;
  source_curve->start.frame = to_source(source_curve->start.frame);
  for (CurveSegment& s : source_curve->segments) {
    s.end.frame = to_source(s.end.frame);
    for (CurvePoint& h : s.handles) h.frame = to_source(h.frame);
  }
}

// The source's key poses (0, the last frame, and options.key_frames or every keyframe time
// rounded to its nearest frame) at their nearest grid frames: several on one grid frame are
// one key pose, and the last grid frame belongs to the clip's last frame.
std::vector<int> RefGridKeys(const Rate& r, const CurveSet& source, const std::vector<int>& given,
                             int grid_frames) {
  const int last = source.frame_count - 1;
  std::set<int> keys = {0, last};
  keys.insert(given.begin(), given.end());
  if (given.empty()) {
    for (const Curve& c : source.curves) {
      if (c.dense()) continue;
      std::vector<double> times = {c.start.frame};
      for (const CurveSegment& s : c.segments) times.push_back(s.end.frame);
      for (double t : times) {
        keys.insert(static_cast<int>(std::clamp(std::round(t), 0.0, static_cast<double>(last))));
      }
    }
  }
  std::set<int> grid;
  for (int k : keys) {
    const int g = NearestGridFrame(r, k);
    if (k != last && g < grid_frames - 1) grid.insert(g);
  }
  grid.insert(grid_frames - 1);
  return {grid.begin(), grid.end()};
}

Clip RandomClip(SplitMix64& rng, const Rate& r, int max_grid_frames) {
  Clip clip;
  // Source frames n with floor((n - 1) q / p) = g - 1 (below 24 fps not every g has one).
  int64_t lo = 0, hi = -1;
  while (hi < lo) {
    clip.grid_frames = rng.Int(2, max_grid_frames);
    lo = ((clip.grid_frames - 1) * r.p + r.q - 1) / r.q;
    hi = (clip.grid_frames * r.p + r.q - 1) / r.q - 1;
  }
  const int g = clip.grid_frames;
  const int n = static_cast<int>(lo + rng.Int(0, static_cast<int>(hi - lo))) + 1;
  clip.source.fps = r.fps();
  clip.source.frame_count = n;
  EXPECT_EQ(RefGridCount(r, n), g);
  clip.reference.fps = static_cast<double>(r.t);
  clip.reference.frame_count = g;
  const bool restricted = rng.OneIn(2);
  clip.source.beziers_restricted = clip.reference.beziers_restricted = restricted;
  const double p = static_cast<double>(r.p), q = static_cast<double>(r.q);
  const auto to_source = [p, q](double t) { return t * p / q; };  // as FilmGrid::SourceTime
  const int curves = rng.Int(1, 5);
  for (int c = 0; c < curves; ++c) {
    Curve grid_curve, source_curve;
    grid_curve.id = source_curve.id = "P" + std::to_string(c);
    if (rng.OneIn(4)) {
      // Dense at the source rate: at 24 fps the same polyline, its points at k * q / p.
      double v = rng.Unit();
      for (int k = 0; k < n; ++k) {
        if (!rng.OneIn(3)) v = rng.Unit() * 2.0 - 1.0;
        source_curve.samples.push_back(v);
      }
      grid_curve.start = {0.0, source_curve.samples[0]};
      for (int k = 1; k < n; ++k) {
        CurveSegment s;
        s.type = SegmentType::kLinear;
        s.end = {k * q / p, source_curve.samples[k]};
        grid_curve.segments.push_back(s);
      }
    } else {
      RandomKeyframes(rng, g, to_source, &grid_curve, &source_curve);
    }
    clip.source.curves.push_back(source_curve);
    clip.reference.curves.push_back(grid_curve);
  }
  KomaUchiOptions& o = clip.options;
  o.timing_fps = static_cast<double>(r.t);
  // The reference's key poses are the source's, named: every keyframe time a key pose (merging
  // on the grid is tested against a naive merge in key_pose_merge_test.cc).
  o.merge_key_poses = false;
  if (rng.OneIn(3)) {
    for (int k = 0; k < n; ++k) {
      if (rng.OneIn(std::max(2, n / 6))) o.key_frames.push_back(k);
    }
  }
  if (!rng.OneIn(3)) o.frames_per_drawing = rng.Int(1, 5);
  if (rng.OneIn(3)) o.tame = 1.0 + rng.Unit() * 2.0;
  if (rng.OneIn(3)) o.tsume = 1.0 + rng.Unit() * 2.0;
  for (int c = 0; c < curves; ++c) {
    if (rng.OneIn(4)) o.curve_frames_per_drawing["P" + std::to_string(c)] = rng.Int(1, 6);
  }
  const std::vector<int> ref_keys = RefGridKeys(r, clip.source, o.key_frames, g);
  for (size_t s = 0; s + 1 < ref_keys.size(); ++s) {
    if (!rng.OneIn(4)) continue;
    SegmentOverride so;
    so.segment = static_cast<int>(s);
    if (rng.OneIn(2)) so.frames_per_drawing = rng.Int(1, 4);
    if (rng.OneIn(2)) so.tame = 1.0 + rng.Unit();
    if (rng.OneIn(2)) so.tsume = 1.0 + rng.Unit();
    o.segment_overrides.push_back(so);
  }
  clip.ref_options = o;
  clip.ref_options.timing_fps = 0.0;
  clip.ref_options.key_frames = ref_keys;
  return clip;
}

// Compares one timing and the curves using it; returns "" or what differs.
// The tau a grid drawing must have: the reference's tau (grid frames, no grid) at the same
// fraction of its segment between the key poses' grid frames `grid_keys`, mapped between the
// key poses' own source frames `source_keys`; the last drawing shows the clip's last frame.
double WantTau(const std::vector<int>& grid_keys, const std::vector<double>& source_keys, int start,
               double ref_tau) {
  const size_t x = static_cast<size_t>(
      std::upper_bound(grid_keys.begin(), grid_keys.end(), start) - grid_keys.begin() - 1);
  if (x + 1 >= grid_keys.size()) return source_keys.back();  // the clip's last frame
  const double fraction = (ref_tau - grid_keys[x]) / (grid_keys[x + 1] - grid_keys[x]);
  return source_keys[x] + (source_keys[x + 1] - source_keys[x]) * fraction;
}

// The key poses' own times (docs/semantics.md): with the poses made from the keyframes, the
// earliest keyframe time of any curve that rounds to the pose's frame (not the clip's ends);
// named poses: their frames.
std::vector<double> PoseTimes(const Clip& clip, const std::vector<int>& frames) {
  std::vector<double> times(frames.begin(), frames.end());
  if (!clip.options.key_frames.empty()) return times;
  const int last = clip.source.frame_count - 1;
  for (size_t x = 0; x < frames.size(); ++x) {
    if (frames[x] == 0 || frames[x] == last) continue;
    double earliest = HUGE_VAL;
    for (const Curve& c : clip.source.curves) {
      if (c.dense()) continue;
      std::vector<double> keys = {c.start.frame};
      for (const CurveSegment& s : c.segments) keys.push_back(s.end.frame);
      for (double t : keys) {
        const double clamped = std::clamp(t, 0.0, static_cast<double>(last));
        if (std::clamp(std::round(t), 0.0, static_cast<double>(last)) == frames[x]) {
          earliest = std::min(earliest, clamped);
        }
      }
    }
    if (earliest < HUGE_VAL) times[x] = earliest;
  }
  return times;
}

std::string CompareTiming(const Rate& r, const Clip& clip, const KomaUchiResult& got_result,
                          const DrawingTiming& got, const DrawingTiming& want) {
  const std::vector<int>& grid_keys = got_result.key_grid_frames;
  const std::vector<double> source_keys = PoseTimes(clip, got_result.key_frames);
  const int n = clip.source.frame_count;
  const int last_grid = clip.grid_frames - 1;
  std::ostringstream why;
  if (got.frames_per_drawing != want.frames_per_drawing) return "frames_per_drawing";
  if (got.drawing_start_grid != want.drawing_start) return "drawing_start_grid";
  const size_t drawings = want.drawing_start.size();
  if (got.drawing_start.size() != drawings || got.drawing_time.size() != drawings ||
      got.drawing_tau.size() != drawings) {
    return "per-drawing sizes";
  }
  if (got.drawing_of_frame.size() != static_cast<size_t>(n) ||
      got.source_frame.size() != static_cast<size_t>(n)) {
    return "per-frame sizes";
  }
  for (size_t d = 0; d < drawings; ++d) {
    const int g = want.drawing_start[d];
    // Start times in seconds: g / 24 s (the ratio's error apart for 29.97).
    const double got_s = got.drawing_time[d] / r.fps(), want_s = g / static_cast<double>(r.t);
    if (std::fabs(got_s - want_s) > (r.ratio_error() + 1e-12) * std::max(1.0, want_s)) {
      why << "drawing " << d << " starts at " << got_s << " s, want " << want_s << " s";
      return why.str();
    }
    if (!Near(got.drawing_time[d], g * r.ratio())) return "drawing_time " + std::to_string(d);
    const double tau = WantTau(grid_keys, source_keys, g, want.source_frame[g]);
    if (!Near(got.drawing_tau[d], tau)) {
      why << "drawing_tau " << d << " " << got.drawing_tau[d] << ", want " << tau;
      return why.str();
    }
  }
  std::vector<int> first_frame(drawings, -1);
  for (int k = 0; k < n; ++k) {
    const std::vector<int> gs = GridFramesOf(r, k, last_grid);
    const auto g = std::find_if(gs.begin(), gs.end(), [&](int f) {
      return want.drawing_of_frame[f] == got.drawing_of_frame[k];
    });
    if (g == gs.end()) {
      why << "source frame " << k << " shows drawing " << got.drawing_of_frame[k]
          << ", grid frame " << gs.back() << " drawing " << want.drawing_of_frame[gs.back()];
      return why.str();
    }
    if (got.source_frame[k] != got.drawing_tau[static_cast<size_t>(got.drawing_of_frame[k])]) {
      why << "source frame " << k << " tau " << got.source_frame[k] << ", not its drawing's";
      return why.str();
    }
    int& first = first_frame[static_cast<size_t>(got.drawing_of_frame[k])];
    if (first < 0) first = k;
  }
  for (size_t d = 0; d < drawings; ++d) {
    // A drawing's first output frame is the first source frame at or after its start,
    // ceil(g p / q) (the last frame at most); the frames show it from there (above 24 fps
    // every grid frame holds a source frame: each drawing shows).
    const int64_t g = want.drawing_start[d];
    const int64_t start = std::min<int64_t>((g * r.p + r.q - 1) / r.q, n - 1);
    if (got.drawing_start[d] != start) {
      why << "drawing " << d << " starts at source frame " << got.drawing_start[d] << ", want "
          << start;
      return why.str();
    }
    if (first_frame[d] < 0 && r.p > r.q) return "drawing " + std::to_string(d) + " never shows";
    if (first_frame[d] >= 0 && first_frame[d] != got.drawing_start[d]) {
      why << "drawing " << d << " starts at source frame " << got.drawing_start[d]
          << ", first shown at " << first_frame[d];
      return why.str();
    }
  }
  return "";
}

std::string CompareCurve(const Rate& r, const Clip& clip, const KomaUchiResult& got_result,
                         size_t c, const KomaUchiResult& want_result) {
  const RetimedCurve& got = got_result.curves[c];
  const RetimedCurve& want = want_result.curves[c];
  std::ostringstream why;
  if (got.timing != want.timing) return "timing index";
  if (got.hold_histogram != want.hold_histogram) return "hold histogram";
  const DrawingTiming& timing = got_result.timings[static_cast<size_t>(got.timing)];
  const int n = clip.source.frame_count;
  const size_t drawings = want.steps.size();
  const double last = n - 1.0;
  const bool extra = want.steps.back().frame * r.ratio() < last - 1e-9;
  if (got.steps.size() != drawings + (extra ? 1 : 0)) {
    why << got.steps.size() << " steps, want " << drawings << (extra ? " + 1" : "");
    return why.str();
  }
  // Each drawing shows the curve at its tau or one of the curve's keys it draws.
  const Curve& curve = clip.source.curves[c];
  for (size_t d = 0; d < drawings; ++d) {
    if (!Near(got.steps[d].frame, want.steps[d].frame * r.ratio())) {
      why << "step " << d << " at " << got.steps[d].frame << ", want "
          << want.steps[d].frame * r.ratio();
      return why.str();
    }
    const double value = got.steps[d].value;
    const bool at_tau =
        value == EvaluateCurve(curve, timing.drawing_tau[d], clip.source.beziers_restricted);
    const bool a_key = std::any_of(got.keys.begin(), got.keys.end(), [&](const KeyDrawing& k) {
      return k.drawn && k.value == value;
    });
    if (!at_tau && !a_key) {
      why << "step " << d << " value " << value << " is neither the curve at its tau nor a key";
      return why.str();
    }
  }
  for (int k = 0; k < n; ++k) {
    const int d = timing.drawing_of_frame[k];
    if (got.values[k] != got.steps[static_cast<size_t>(d)].value) {
      why << "frame " << k << " value " << got.values[k] << ", not its drawing's";
      return why.str();
    }
  }
  if (extra && (got.steps.back().frame != last || got.steps.back().value != got.steps[drawings - 1].value)) {
    return "the last step does not hold the last drawing to the clip's end";
  }
  return "";
}

class CurvesGridPropertyTest : public ::testing::TestWithParam<Rate> {};

TEST_P(CurvesGridPropertyTest, GridRetimingEqualsRetimingAt24FpsExpanded) {
  const Rate r = GetParam();
  // The grid's ratio is the p / q this test converts with.
  const std::optional<FilmGrid> grid = FilmGrid::Make(r.fps(), static_cast<double>(r.t));
  ASSERT_TRUE(grid.has_value());
  ASSERT_EQ(grid->SourceTime(static_cast<double>(r.q)), static_cast<double>(r.p));
  ASSERT_EQ(grid->GridFrameOf(static_cast<int>(r.p)), r.q);
  ASSERT_EQ(grid->GridFrameOf(static_cast<int>(r.p) - 1), ((r.p - 1) * r.q) / r.p);
  ASSERT_LE(r.ratio_error(), 1e-4);
  int failures = 0;
  int grid_keys_merged = 0;
  for (uint64_t seed = 1; seed <= kClipsPerRate && failures < 3; ++seed) {
    SplitMix64 rng(seed * 6151 + static_cast<uint64_t>(r.num));
    const Clip clip = RandomClip(rng, r, 90);
    const std::string context = "seed " + std::to_string(seed) + ", " +
                                std::to_string(clip.source.frame_count) + " frames at " +
                                std::to_string(r.fps()) + " fps, " +
                                std::to_string(clip.grid_frames) + " grid frames";
    ASSERT_THAT(ValidateCurveSet(clip.source), IsOk()) << context;
    ASSERT_THAT(ValidateCurveSet(clip.reference), IsOk()) << context;
    ASSERT_THAT(ValidateKomaUchiOptions(clip.options, clip.source), IsOk()) << context;
    ASSERT_THAT(ValidateKomaUchiOptions(clip.ref_options, clip.reference), IsOk()) << context;
    const KomaUchiResult got = RetimeCurves(clip.source, clip.options);
    const KomaUchiResult want = RetimeCurves(clip.reference, clip.ref_options);
    std::string why;
    if (got.timing_fps != static_cast<double>(r.t)) why = "timing_fps";
    if (why.empty() && got.key_grid_frames != want.key_frames) why = "key_grid_frames";
    if (why.empty() && got.key_frames.size() != got.key_grid_frames.size()) why = "key_frames";
    for (size_t i = 0; why.empty() && i + 1 < got.key_frames.size(); ++i) {
      if (NearestGridFrame(r, got.key_frames[i]) != got.key_grid_frames[i]) {
        why = "key_frames[" + std::to_string(i) + "] is not at its grid frame";
      }
    }
    if (why.empty() && got.key_frames.back() != clip.source.frame_count - 1) why = "last key";
    if (why.empty() && got.timings.size() != want.timings.size()) why = "timing count";
    for (size_t t = 0; why.empty() && t < got.timings.size(); ++t) {
      why = CompareTiming(r, clip, got, got.timings[t], want.timings[t]);
      if (!why.empty()) why = "timings[" + std::to_string(t) + "]: " + why;
    }
    for (size_t c = 0; why.empty() && c < got.curves.size(); ++c) {
      why = CompareCurve(r, clip, got, c, want);
      if (!why.empty()) why = "curves[" + std::to_string(c) + "]: " + why;
    }
    if (!why.empty()) {
      ++failures;
      ADD_FAILURE() << context << ": " << why;
    }
    if (got.key_frames.size() < KeyPoses(clip.options, clip.source).size()) ++grid_keys_merged;
  }
  // Key poses merge only where the grid is coarser than the source.
  if (r.p > r.q) {
    EXPECT_GT(grid_keys_merged, 0) << "no clip had key poses merging on the grid";
  } else {
    EXPECT_EQ(grid_keys_merged, 0);
  }
}

// Drawing d's shown time in seconds: from its start time to the next drawing's (the last
// drawing's is cut by the clip's end), and the source frames that show it.
TEST_P(CurvesGridPropertyTest, DrawingsLastOneToNGridFramesAndStepsGiveBackTheValues) {
  const Rate r = GetParam();
  const double grid_s = 1.0 / static_cast<double>(r.t), source_s = 1.0 / r.fps();
  int failures = 0;
  for (uint64_t seed = 1; seed <= kClipsPerRate && failures < 3; ++seed) {
    SplitMix64 rng(seed * 15485863 + static_cast<uint64_t>(r.num));
    Clip clip = RandomClip(rng, r, 200);
    if (rng.OneIn(2)) clip.options = KomaUchiOptions{};  // the defaults, n = 3
    clip.options.timing_fps = static_cast<double>(r.t);
    clip.options.segment_overrides.clear();  // defaults may differ in key count
    if (!ValidateKomaUchiOptions(clip.options, clip.source).ok()) continue;
    const KomaUchiResult got = RetimeCurves(clip.source, clip.options);
    const std::string context =
        "seed " + std::to_string(seed) + ", " + std::to_string(clip.source.frame_count) +
        " frames at " + std::to_string(r.fps()) + " fps";
    const int n = clip.source.frame_count;
    std::string why;
    for (size_t t = 0; why.empty() && t < got.timings.size(); ++t) {
      const DrawingTiming& timing = got.timings[t];
      const int most = std::max(timing.frames_per_drawing, 6);  // segment overrides go to 4
      std::vector<int> shown(timing.drawing_start.size(), 0);
      for (int d : timing.drawing_of_frame) ++shown[static_cast<size_t>(d)];
      const size_t drawings = timing.drawing_time.size();
      for (size_t d = 0; why.empty() && d + 1 < drawings; ++d) {
        const double held_s = (timing.drawing_time[d + 1] - timing.drawing_time[d]) * source_s;
        const double tol = r.ratio_error() * 10 + 1e-12;
        // Within one timing n may differ per segment (curve n wins): allow the largest.
        if (held_s < grid_s * (1 - tol) || held_s > most * grid_s * (1 + tol)) {
          why = "drawing " + std::to_string(d) + " held " + std::to_string(held_s * 1000) + " ms";
        }
        const double shown_s = shown[d] * source_s;
        if (r.p > r.q && (shown_s < grid_s - source_s - 1e-9 || shown_s > most * grid_s + source_s + 1e-9)) {
          why = "drawing " + std::to_string(d) + " shown " + std::to_string(shown_s * 1000) +
                " ms at the source rate";
        }
      }
    }
    for (size_t c = 0; why.empty() && c < got.curves.size(); ++c) {
      const RetimedCurve& curve = got.curves[c];
      const DrawingTiming& timing = got.timings[static_cast<size_t>(curve.timing)];
      // Held no longer than the curve's own n grid frames, per the histogram.
      const int n_curve = clip.options.curve_frames_per_drawing.count(clip.source.curves[c].id)
                              ? clip.options.curve_frames_per_drawing.at(clip.source.curves[c].id)
                              : clip.options.frames_per_drawing;
      // Between merged key poses (the defaults) holds are floor(L / n): up to 2n - 1 frames.
      const int longest = MergesKeyPoses(clip.options) ? 2 * n_curve - 1 : n_curve;
      if (curve.hold_histogram.rbegin()->first > longest) why = "a hold over n grid frames";
      if (curve.hold_histogram.begin()->first < 1) why = "an empty hold";
      (void)timing;
      Curve stepped;
      stepped.id = "s";
      stepped.start = curve.steps.front();
      for (size_t i = 1; i < curve.steps.size(); ++i) {
        CurveSegment s;
        s.type = SegmentType::kStepped;
        s.end = curve.steps[i];
        stepped.segments.push_back(s);
      }
      for (int k = 0; why.empty() && k < n; ++k) {
        if (EvaluateCurve(stepped, k, false) != curve.values[k]) {
          why = "curves[" + std::to_string(c) + "]: the stepped keys at frame " +
                std::to_string(k) + " give " + std::to_string(EvaluateCurve(stepped, k, false)) +
                ", values " + std::to_string(curve.values[k]);
        }
      }
    }
    if (!why.empty()) {
      ++failures;
      ADD_FAILURE() << context << ": " << why;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Rates, CurvesGridPropertyTest, ::testing::ValuesIn(Rates()),
                         ::koma::testing::GridRateName());

// 24 fps input is not on a grid: timing_fps 24 (and 24 +- 1e-4 relative) answers exactly as
// timing_fps 0.
TEST(CurvesGridTest, TwentyFourFpsAnswersAsWithoutAGrid) {
  const Rate at24{24, 1, 1, 1};
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    SplitMix64 rng(seed);
    Clip clip = RandomClip(rng, at24, 60);
    for (double fps : {24.0, 24.0 * (1 + 0.9e-4), 24.0 * (1 - 0.9e-4)}) {
      clip.source.fps = fps;
      KomaUchiOptions plain = clip.options;
      plain.timing_fps = 0.0;
      ASSERT_THAT(ValidateKomaUchiOptions(clip.options, clip.source), IsOk());
      const KomaUchiResult a = RetimeCurves(clip.source, clip.options);
      const KomaUchiResult b = RetimeCurves(clip.source, plain);
      ASSERT_EQ(a.timing_fps, 0.0);
      ASSERT_TRUE(a.key_grid_frames.empty());
      ASSERT_EQ(a.key_frames, b.key_frames);
      ASSERT_EQ(a.timings.size(), b.timings.size());
      for (size_t t = 0; t < a.timings.size(); ++t) {
        ASSERT_EQ(a.timings[t].drawing_of_frame, b.timings[t].drawing_of_frame);
        ASSERT_EQ(a.timings[t].source_frame, b.timings[t].source_frame);
        ASSERT_EQ(a.timings[t].drawing_start, b.timings[t].drawing_start);
        ASSERT_TRUE(a.timings[t].drawing_start_grid.empty());
      }
      for (size_t c = 0; c < a.curves.size(); ++c) {
        ASSERT_EQ(a.curves[c].values, b.curves[c].values);
        ASSERT_EQ(a.curves[c].hold_histogram, b.curves[c].hold_histogram);
      }
    }
  }
}

// A 30 fps motion with its first and last key pose only, on threes: 8 drawings in every
// 1-second stretch [t, t + 1) of the clip, each stepped key on a multiple of 1/24 s.
TEST(CurvesGridTest, ThirtyFpsOnThreesShowsEightDrawingsASecond) {
  for (int grid_frames = 25; grid_frames <= 25 + 3 * 60; grid_frames += 3) {
    // grid_frames - 1 is a multiple of 3: every hold is 3 grid frames, the last key's too.
    for (int extra = 0; extra < 2; ++extra) {
      CurveSet set;
      set.fps = 30.0;
      // Source frames n with floor((n - 1) * 24 / 30) = grid_frames - 1 (extra: the last one).
      const int lo = ((grid_frames - 1) * 5 + 3) / 4;
      const int hi = (grid_frames * 5 + 3) / 4 - 1;
      set.frame_count = (extra ? hi : lo) + 1;
      Curve curve;
      curve.id = "ParamAngleX";
      curve.start = {0.0, 0.0};
      CurveSegment s;
      s.type = SegmentType::kLinear;
      s.end = {set.frame_count - 1.0, 30.0};
      curve.segments.push_back(s);
      set.curves.push_back(curve);
      KomaUchiOptions options;  // n = 3
      options.timing_fps = kDefaultTimingFps;
      ASSERT_THAT(ValidateKomaUchiOptions(options, set), IsOk());
      const KomaUchiResult result = RetimeCurves(set, options);
      ASSERT_EQ(result.key_grid_frames, (std::vector<int>{0, grid_frames - 1}));
      const std::vector<CurvePoint>& steps = result.curves[0].steps;
      std::vector<double> starts_s;  // drawings' start times, seconds
      for (size_t d = 0; d < result.timings[0].drawing_start.size(); ++d) {
        const double s_24 = steps[d].frame / 30.0 * 24.0;
        ASSERT_NEAR(s_24, std::round(s_24), 1e-9) << "step " << d << " at " << steps[d].frame;
        starts_s.push_back(steps[d].frame / 30.0);
      }
      const double end_s = (set.frame_count - 1) / 30.0;
      ASSERT_GE(end_s, 1.0);
      for (double t = 0.0; t + 1.0 <= end_s + 1e-12; t += 1.0 / 240.0) {
        const auto in = std::count_if(starts_s.begin(), starts_s.end(), [t](double start) {
          return start >= t - 1e-12 && start < t + 1.0 - 1e-12;
        });
        ASSERT_EQ(in, 8) << set.frame_count << " frames, [" << t << ", " << t + 1 << ") s";
      }
      // Also every stretch starting on a drawing.
      for (double t : starts_s) {
        if (t + 1.0 > end_s + 1e-12) break;
        const auto in = std::count_if(starts_s.begin(), starts_s.end(), [t](double start) {
          return start >= t - 1e-12 && start < t + 1.0 - 1e-12;
        });
        ASSERT_EQ(in, 8) << set.frame_count << " frames, [" << t << ", " << t + 1 << ") s";
      }
      // Hold histogram: all 3 grid frames, plus the last key's 1.
      std::map<int, int> want = {{3, (grid_frames - 1) / 3}, {1, 1}};
      EXPECT_EQ(result.curves[0].hold_histogram, want);
    }
  }
}

}  // namespace
}  // namespace koma

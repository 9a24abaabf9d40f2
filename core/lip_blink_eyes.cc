// ConvertEyes (docs/semantics.md, "LipBlink", paper section 3.2.2, Eq. 5-7): levels, blink
// detection (linked on the normalised mean, or per curve), and the anime repaint: open snaps
// to closed, closed for at least k frames, half-open for k frames, then open.
#include <algorithm>
#include <cassert>
#include <optional>
#include <vector>

#include "core/lip_blink.h"
#include "core/lip_blink_given.h"
#include "core/lip_blink_internal.h"

namespace koma {
namespace {

// Paper Eq. 7: the hold k from O_total = (C_end - C_start) + O_span, in frames.
int HoldFromOTotal(int o_total) {
  if (o_total <= 3) return 1;
  if (o_total <= 5) return 2;
  return 3;
}

// The last frame painted closed: the closed run, stretched to k frames when shorter.
int ClosedLast(const Blink& b) { return std::max(b.closed_end, b.closed_begin + b.hold - 1); }

}  // namespace

namespace lip_blink_internal {

Extent ExtentOf(absl::Span<const double> values) {
  if (values.empty()) return {};
  double lo[4] = {values[0], values[0], values[0], values[0]};
  double hi[4] = {values[0], values[0], values[0], values[0]};
  const size_t n = values.size();
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    for (int k = 0; k < 4; ++k) {
      const double v = values[i + k];
      lo[k] = v < lo[k] ? v : lo[k];
      hi[k] = v > hi[k] ? v : hi[k];
    }
  }
  for (; i < n; ++i) {
    lo[0] = values[i] < lo[0] ? values[i] : lo[0];
    hi[0] = values[i] > hi[0] ? values[i] : hi[0];
  }
  return {std::min(std::min(lo[0], lo[1]), std::min(lo[2], lo[3])),
          std::max(std::max(hi[0], hi[1]), std::max(hi[2], hi[3]))};
}

std::vector<FrameInterval> ClosedRuns(absl::Span<const double> signal, double closed_at_most) {
  const int frame_count = static_cast<int>(signal.size());
  std::vector<FrameInterval> runs;
  for (int f = 0; f < frame_count;) {
    if (signal[f] > closed_at_most) {
      ++f;
      continue;
    }
    const int begin = f;
    while (f < frame_count && signal[f] <= closed_at_most) ++f;
    runs.push_back({begin, f});
  }
  return runs;
}

namespace {

// The top of one side of a closed run: where the eye stops opening (after) or starts closing
// (before), on the frames [lo, hi) between this run and the next one (or the clip's edge).
struct Top {
  bool found = false;
  double value = 0.0;
  bool held = false;  // open at `value` for kHeldFrames frames, away from the run
};

// Walking away from the run (step +1 from lo, -1 from hi - 1): the first frame that none of
// the next kHeldFrames - 1 frames (within [lo, hi)) exceeds. Always found on a non-empty side:
// the far end has nothing beyond it.
Top TopOfSide(absl::Span<const double> s, int lo, int hi, int step, double closed, double delta) {
  Top top;
  if (lo >= hi) return top;
  const int first = step > 0 ? lo : hi - 1;
  const auto inside = [lo, hi](int f) { return f >= lo && f < hi; };
  for (int f = first; inside(f); f += step) {
    bool exceeded = false;
    for (int g = f + step, n = 1; n < kHeldFrames && inside(g); g += step, ++n) {
      if (s[g] > s[f]) {
        exceeded = true;
        break;
      }
    }
    if (exceeded) continue;
    top.found = true;
    top.value = s[f];
    const double open_at_least = OpenAtLeast(top.value, closed, delta);
    top.held = inside(f + step * (kHeldFrames - 1));
    for (int g = f, n = 0; top.held && n < kHeldFrames; g += step, ++n) {
      top.held = s[g] >= open_at_least;
    }
    return top;
  }
  return top;
}

// A side keeps its own top when the eye is held there or the top is open at the other side's
// level; else the eye is only passing through it (a half-open frame between two closings, the
// clip starting mid-closing) and the side takes the other side's level, as the paper reads
// such frames against E_max.
double Resolve(const Top& own, const Top& other, double closed, double delta) {
  if (own.held || own.value >= OpenAtLeast(other.value, closed, delta)) return own.value;
  return other.value;
}

}  // namespace

std::vector<BlinkLevels> OpenLevelsAround(absl::Span<const double> signal,
                                          const std::vector<FrameInterval>& runs, double closed,
                                          double delta, std::optional<double> fixed,
                                          double fallback) {
  const int frame_count = static_cast<int>(signal.size());
  std::vector<BlinkLevels> levels(runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    if (fixed) {
      levels[i] = {*fixed, *fixed};
      continue;
    }
    const int before_lo = i > 0 ? runs[i - 1].end : 0;
    const int after_hi = i + 1 < runs.size() ? runs[i + 1].begin : frame_count;
    const Top before = TopOfSide(signal, before_lo, runs[i].begin, -1, closed, delta);
    const Top after = TopOfSide(signal, runs[i].end, after_hi, +1, closed, delta);
    if (!before.found && !after.found) {
      levels[i] = {fallback, fallback};
    } else if (!before.found || !after.found) {
      const double level = before.found ? before.value : after.value;
      levels[i] = {level, level};
    } else {
      levels[i] = {Resolve(before, after, closed, delta), Resolve(after, before, closed, delta)};
    }
  }
  return levels;
}

// Where two closed runs have no frame open at the levels between them, the frames between
// are the first blink's opening span (its O_span stops at the next closed run) and the second
// blink has no closing phase: closed -> half -> open -> closed keeps both blinks' anime shape.
// Before the clip's first open frame the closing phase reaches back to frame 0.
std::vector<Blink> DetectBlinks(absl::Span<const double> signal, double closed_at_most,
                                double closed, double delta, std::optional<double> fixed,
                                double fallback) {
  const int frame_count = static_cast<int>(signal.size());
  const std::vector<FrameInterval> runs = ClosedRuns(signal, closed_at_most);
  const std::vector<BlinkLevels> levels =
      OpenLevelsAround(signal, runs, closed, delta, fixed, fallback);
  std::vector<Blink> blinks;
  blinks.reserve(runs.size());
  for (size_t i = 0; i < runs.size(); ++i) {
    Blink b;
    b.closed_begin = runs[i].begin;
    b.closed_end = runs[i].end - 1;
    // The closing phase: back to the last frame open at the level the eye closes from.
    const int lower = i > 0 ? runs[i - 1].end : 0;
    const double closing_open = OpenAtLeast(levels[i].before, closed, delta);
    int f = b.closed_begin;
    while (f > lower && signal[f - 1] < closing_open) --f;
    const bool open_before = f > lower;  // signal[f - 1] is open
    b.closing_begin = open_before || i == 0 ? f : b.closed_begin;
    // O_span: after C_end until the first frame open at the level it reopens to, the next
    // closed one or the end.
    const double reopen = OpenAtLeast(levels[i].after, closed, delta);
    int o = runs[i].end;
    while (o < frame_count && signal[o] < reopen && signal[o] > closed_at_most) ++o;
    b.open_span = o - runs[i].end;
    b.hold = HoldFromOTotal(b.closed_end - b.closed_begin + b.open_span);
    blinks.push_back(b);
  }
  return blinks;
}

std::vector<int> PaintEnds(const std::vector<Blink>& blinks, int frame_count) {
  std::vector<int> ends(blinks.size());
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    const int limit = i + 1 < blinks.size() ? blinks[i + 1].closing_begin : frame_count;
    // The opening span, or further when the stretched closed run plus k half-open frames
    // outlast it.
    const int end = std::max(b.closed_end + 1 + b.open_span, ClosedLast(b) + 1 + b.hold);
    ends[i] = std::min(end, limit);
  }
  return ends;
}

}  // namespace lip_blink_internal

namespace {

using lip_blink_internal::kFlatRange;
using lip_blink_internal::OpenAtLeast;

struct Levels {
  double closed = 0.0, mid = 0.0, open = 0.0;  // E_min, E_mid, E_max
  bool flat = false;                           // the input's own range is below kFlatRange
};

// E_min and E_max given, or the curve's min and max; a flat curve (range < kFlatRange) closes
// at 0 unless min is given (Live2D: 0 = eye shut), so an auto-blink on a flat open eye shows.
Levels LevelsOf(absl::Span<const double> curve, const EyeOptions& options) {
  const lip_blink_internal::Extent extent = lip_blink_internal::ExtentOf(curve);
  Levels levels;
  levels.flat = extent.max - extent.min < kFlatRange;
  levels.closed = options.min.value_or(levels.flat ? 0.0 : extent.min);
  levels.open = options.max.value_or(extent.max);
  levels.mid = levels.closed + options.mid_ratio * (levels.open - levels.closed);
  return levels;
}

bool Detectable(const Levels& l) { return l.open - l.closed >= kFlatRange; }

// The closed runs of detected blinks (automatic ones have none in the input).
std::vector<FrameInterval> DetectedRuns(const std::vector<Blink>& blinks) {
  std::vector<FrameInterval> runs;
  for (const Blink& b : blinks) {
    if (!b.automatic) runs.push_back({b.closed_begin, b.closed_end + 1});
  }
  return runs;
}

// One eye curve's open levels at each of `blinks` (docs/semantics.md, "LipBlink", "Open
// levels"): E_max when given; at a detected blink the input's own levels either side of its
// closed run (OpenLevelsAround, on this curve's frames); at an inserted blink the input's level
// where it ends (the frame after it, or the clip's last frame).
std::vector<BlinkLevels> CurveLevels(absl::Span<const double> eye, const std::vector<Blink>& blinks,
                                     const Levels& l, const EyeOptions& options) {
  const std::vector<BlinkLevels> detected = lip_blink_internal::OpenLevelsAround(
      eye, DetectedRuns(blinks), l.closed, options.threshold, options.max, l.open);
  const int last = static_cast<int>(eye.size()) - 1;
  std::vector<BlinkLevels> levels;
  levels.reserve(blinks.size());
  size_t d = 0;
  for (const Blink& b : blinks) {
    if (!b.automatic) {
      levels.push_back(detected[d++]);
      continue;
    }
    const double there =
        options.max ? *options.max : eye[std::min(b.closed_begin + 2 * b.hold, last)];
    levels.push_back({there, there});
  }
  return levels;
}

// Linked: each detected blink's closing phase starts where the first eye's starts. The mean
// leaves "open" only once the eyes together have closed by delta, so an eye that starts
// closing a frame or two before the others would show its half-closed values before the
// snap (1, 0.833, 1, 0: a flicker). Each eye's closing phase begins after its own last frame
// open at its own level before the blink (as unlinked), and the blink's closing phase is the
// earliest of them, never reaching back into the previous blink's repaint (PaintEnds) or
// before frame 0.
void StartClosingWithTheFirstEye(const std::vector<absl::Span<const double>>& eyes,
                                 const std::vector<Levels>& levels, const std::vector<bool>& used,
                                 const EyeOptions& options, int frame_count,
                                 std::vector<Blink>& blinks) {
  const std::vector<int> ends = lip_blink_internal::PaintEnds(blinks, frame_count);
  std::vector<std::vector<BlinkLevels>> own(eyes.size());
  for (size_t c = 0; c < eyes.size(); ++c) {
    if (used[c]) own[c] = CurveLevels(eyes[c], blinks, levels[c], options);
  }
  for (size_t i = 0; i < blinks.size(); ++i) {
    Blink& b = blinks[i];
    const int lower = i > 0 ? ends[i - 1] : 0;
    int begin = b.closing_begin;
    for (size_t c = 0; c < eyes.size(); ++c) {
      if (!used[c]) continue;
      const double open_at_least =
          OpenAtLeast(own[c][i].before, levels[c].closed, options.threshold);
      int f = b.closing_begin;  // this eye's closing phase: back to its last open frame
      while (f > lower && eyes[c][f - 1] < open_at_least) --f;
      begin = std::min(begin, f);
    }
    b.closing_begin = begin;
  }
}

// Linked: the per-frame mean of (e - E_min) / (E_max - E_min), closed at or below delta, over
// the curves that can carry a timing: not flat (a motion that animates only the left eye still
// blinks both; a flat open curve in the mean would keep it from ever closing) and with levels
// spanning a range. Its open levels are read on the mean as on one curve (1 when E_max is
// given). The others are still painted with the shared blinks.
std::vector<Blink> DetectLinked(const std::vector<absl::Span<const double>>& eyes,
                                const std::vector<Levels>& levels, int frame_count,
                                const EyeOptions& options) {
  std::vector<double> mean(static_cast<size_t>(frame_count), 0.0);
  int used = 0;
  std::vector<bool> in_mean(eyes.size(), false);
  for (size_t c = 0; c < eyes.size(); ++c) {
    if (levels[c].flat || !Detectable(levels[c])) continue;
    in_mean[c] = true;
    // Times the reciprocal rather than a division per frame (several times slower); IEEE
    // multiplication gives the same bits everywhere all the same.
    const double scale = 1.0 / (levels[c].open - levels[c].closed);
    const double closed = levels[c].closed;
    for (int f = 0; f < frame_count; ++f) mean[f] += (eyes[c][f] - closed) * scale;
    ++used;
  }
  if (used == 0) return {};
  for (double& m : mean) m /= used;
  const double delta = options.threshold;
  const std::optional<double> fixed = options.max ? std::optional<double>(1.0) : std::nullopt;
  std::vector<Blink> blinks = lip_blink_internal::DetectBlinks(mean, delta, 0.0, delta, fixed, 1.0);
  StartClosingWithTheFirstEye(eyes, levels, in_mean, options, frame_count, blinks);
  return blinks;
}

std::vector<Blink> DetectOne(absl::Span<const double> eye, const Levels& l,
                             const EyeOptions& options) {
  if (!Detectable(l)) return {};
  const double range = l.open - l.closed;
  return lip_blink_internal::DetectBlinks(eye, l.closed + options.threshold * range, l.closed,
                                          options.threshold, options.max, l.open);
}

// Closing phase -> the level before; closed through ClosedLast; k frames half-open (between
// closed and the level after); the level after to the end.
std::vector<double> Paint(absl::Span<const double> eye, const std::vector<Blink>& blinks,
                          const std::vector<BlinkLevels>& open, double closed, double mid_ratio) {
  std::vector<double> values(eye.begin(), eye.end());
  const std::vector<int> ends =
      lip_blink_internal::PaintEnds(blinks, static_cast<int>(values.size()));
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    // Each stop is within [closed_begin + 1, ends[i]]: ends[i] > closed_end always.
    const int closed_stop = std::min(ends[i], ClosedLast(b) + 1);
    const int mid_stop = std::min(ends[i], closed_stop + b.hold);
    const double mid = closed + mid_ratio * (open[i].after - closed);
    const auto at = [&values](int f) { return values.begin() + f; };
    std::fill(at(b.closing_begin), at(b.closed_begin), open[i].before);
    std::fill(at(b.closed_begin), at(closed_stop), closed);
    std::fill(at(closed_stop), at(mid_stop), mid);
    std::fill(at(mid_stop), at(ends[i]), open[i].after);
  }
  return values;
}

}  // namespace

EyeResult ConvertEyes(const std::vector<absl::Span<const double>>& eyes, const EyeOptions& options,
                      uint64_t seed) {
  EyeResult result;
  if (eyes.empty()) return result;
  const int frame_count = static_cast<int>(eyes[0].size());
  assert(ValidateEyeOptions(options, frame_count).ok());
  std::vector<Levels> levels;
  for (absl::Span<const double> eye : eyes) {
    assert(static_cast<int>(eye.size()) == frame_count);
    levels.push_back(LevelsOf(eye, options));
    result.closed.push_back(levels.back().closed);
    result.mid.push_back(levels.back().mid);
    result.open.push_back(levels.back().open);
  }
  std::vector<Blink> shared;
  if (options.linked) {
    shared = lip_blink_internal::InsertAutoBlinks(DetectLinked(eyes, levels, frame_count, options),
                                                  frame_count, options, seed);
  }
  for (size_t c = 0; c < eyes.size(); ++c) {
    // Unlinked: each curve on its own, its auto-blinks from a fresh stream of the same seed,
    // so a curve's result does not depend on the other curves or their order.
    result.blinks.push_back(
        options.linked ? shared
                       : lip_blink_internal::InsertAutoBlinks(
                             DetectOne(eyes[c], levels[c], options), frame_count, options, seed));
    result.levels.push_back(CurveLevels(eyes[c], result.blinks.back(), levels[c], options));
    result.values.push_back(Paint(eyes[c], result.blinks.back(), result.levels.back(),
                                  levels[c].closed, options.mid_ratio));
  }
  return result;
}

EyeResult PaintGivenEyes(const std::vector<absl::Span<const double>>& eyes,
                         const EyeOptions& options, const std::vector<std::vector<Blink>>& blinks) {
  EyeResult result;
  for (size_t c = 0; c < eyes.size(); ++c) {
    const Levels levels = LevelsOf(eyes[c], options);
    result.closed.push_back(levels.closed);
    result.mid.push_back(levels.mid);
    result.open.push_back(levels.open);
    result.blinks.push_back(blinks[c]);
    result.levels.push_back(CurveLevels(eyes[c], blinks[c], levels, options));
    result.values.push_back(
        Paint(eyes[c], blinks[c], result.levels.back(), levels.closed, options.mid_ratio));
  }
  return result;
}

std::vector<MouthShape> BlinkDrawings(const std::vector<Blink>& blinks, int frame_count) {
  const int n = std::max(frame_count, 0);
  std::vector<MouthShape> drawings(static_cast<size_t>(n), MouthShape::kOpen);
  const std::vector<int> ends = lip_blink_internal::PaintEnds(blinks, n);
  const auto fill = [&drawings, n](int from, int to, MouthShape shape) {
    for (int f = std::max(from, 0); f < std::min(to, n); ++f) drawings[f] = shape;
  };
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    const int closed_stop = std::min(ends[i], ClosedLast(b) + 1);
    const int mid_stop = std::min(ends[i], closed_stop + b.hold);
    fill(b.closed_begin, closed_stop, MouthShape::kClosed);
    fill(closed_stop, mid_stop, MouthShape::kMid);
  }
  return drawings;
}

}  // namespace koma

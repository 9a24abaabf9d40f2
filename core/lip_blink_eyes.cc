// ConvertEyes (docs/semantics.md, "LipBlink", paper section 3.2.2, Eq. 5-7): levels, blink
// detection (linked on the normalised mean, or per curve), and the anime repaint: open snaps
// to closed, closed for at least k frames, half-open for k frames, then open.
#include <algorithm>
#include <cassert>
#include <vector>

#include "core/lip_blink.h"
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

// One forward pass; each frame is read at most twice (once more while counting an O_span).
// Where two closed runs have no open frame between them, the frames between are the first
// blink's opening span (its O_span stops at the next closed run) and the second blink has no
// closing phase: closed -> half -> open -> closed keeps both blinks' anime shape. Before the
// clip's first open frame the closing phase reaches back to frame 0.
std::vector<Blink> DetectBlinks(absl::Span<const double> signal, double closed_at_most,
                                double open_at_least) {
  const int frame_count = static_cast<int>(signal.size());
  const auto closed = [&](int f) { return signal[f] <= closed_at_most; };
  const auto open = [&](int f) { return signal[f] >= open_at_least; };
  std::vector<Blink> blinks;
  int closing_from = 0;  // first frame of the next closing phase; -1: none (see above)
  for (int f = 0; f < frame_count;) {
    if (!closed(f)) {
      if (open(f)) closing_from = f + 1;
      ++f;
      continue;
    }
    Blink b;
    b.closed_begin = f;
    while (f < frame_count && closed(f)) ++f;
    b.closed_end = f - 1;
    b.closing_begin = closing_from < 0 ? b.closed_begin : closing_from;
    int o = f;  // O_span: after C_end until the first open frame, the next closed one or the end
    while (o < frame_count && !open(o) && !closed(o)) ++o;
    b.open_span = o - f;
    b.hold = HoldFromOTotal(b.closed_end - b.closed_begin + b.open_span);
    blinks.push_back(b);
    closing_from = -1;
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

struct Levels {
  double closed = 0.0, mid = 0.0, open = 0.0;
  bool flat = false;  // the input's own range is below kFlatRange
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

// Linked: each detected blink's closing phase starts where the first eye's starts. The mean
// leaves "open" only once the eyes together have closed by delta, so an eye that starts
// closing a frame or two before the others would show its half-closed values before the
// snap (1, 0.833, 1, 0: a flicker). Each eye's closing phase begins after its own last open
// frame before the blink (as unlinked), and the blink's closing phase is the earliest of
// them, never reaching back into the previous blink's repaint (PaintEnds) or before frame 0.
void StartClosingWithTheFirstEye(const std::vector<absl::Span<const double>>& eyes,
                                 const std::vector<Levels>& levels, const std::vector<bool>& used,
                                 double delta, int frame_count, std::vector<Blink>& blinks) {
  const std::vector<int> ends = lip_blink_internal::PaintEnds(blinks, frame_count);
  for (size_t i = 0; i < blinks.size(); ++i) {
    Blink& b = blinks[i];
    const int lower = i > 0 ? ends[i - 1] : 0;
    int begin = b.closing_begin;
    for (size_t c = 0; c < eyes.size(); ++c) {
      if (!used[c]) continue;
      const double open_at_least = levels[c].open - delta * (levels[c].open - levels[c].closed);
      int f = b.closing_begin;  // this eye's closing phase: back to its last open frame
      while (f > lower && eyes[c][f - 1] < open_at_least) --f;
      begin = std::min(begin, f);
    }
    b.closing_begin = begin;
  }
}

// Linked: the per-frame mean of (e - E_min) / (E_max - E_min), thresholds delta and 1 - delta,
// over the curves that can carry a timing: not flat (a motion that animates only the left
// eye still blinks both; a flat open curve in the mean would keep it from ever closing) and
// with levels spanning a range. The others are still painted with the shared blinks.
std::vector<Blink> DetectLinked(const std::vector<absl::Span<const double>>& eyes,
                                const std::vector<Levels>& levels, int frame_count, double delta) {
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
  std::vector<Blink> blinks = lip_blink_internal::DetectBlinks(mean, delta, 1.0 - delta);
  StartClosingWithTheFirstEye(eyes, levels, in_mean, delta, frame_count, blinks);
  return blinks;
}

std::vector<Blink> DetectOne(absl::Span<const double> eye, const Levels& l, double delta) {
  if (!Detectable(l)) return {};
  const double range = l.open - l.closed;
  return lip_blink_internal::DetectBlinks(eye, l.closed + delta * range, l.open - delta * range);
}

// Closing phase -> open; closed through ClosedLast; k frames half-open; open to the end.
std::vector<double> Paint(absl::Span<const double> eye, const std::vector<Blink>& blinks,
                          const Levels& l) {
  std::vector<double> values(eye.begin(), eye.end());
  const std::vector<int> ends =
      lip_blink_internal::PaintEnds(blinks, static_cast<int>(values.size()));
  for (size_t i = 0; i < blinks.size(); ++i) {
    const Blink& b = blinks[i];
    // Each stop is within [closed_begin + 1, ends[i]]: ends[i] > closed_end always.
    const int closed_stop = std::min(ends[i], ClosedLast(b) + 1);
    const int mid_stop = std::min(ends[i], closed_stop + b.hold);
    const auto at = [&values](int f) { return values.begin() + f; };
    std::fill(at(b.closing_begin), at(b.closed_begin), l.open);
    std::fill(at(b.closed_begin), at(closed_stop), l.closed);
    std::fill(at(closed_stop), at(mid_stop), l.mid);
    std::fill(at(mid_stop), at(ends[i]), l.open);
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
    shared = lip_blink_internal::InsertAutoBlinks(
        DetectLinked(eyes, levels, frame_count, options.threshold), frame_count, options, seed);
  }
  for (size_t c = 0; c < eyes.size(); ++c) {
    // Unlinked: each curve on its own, its auto-blinks from a fresh stream of the same seed,
    // so a curve's result does not depend on the other curves or their order.
    result.blinks.push_back(options.linked ? shared
                                           : lip_blink_internal::InsertAutoBlinks(
                                                 DetectOne(eyes[c], levels[c], options.threshold),
                                                 frame_count, options, seed));
    result.values.push_back(Paint(eyes[c], result.blinks.back(), levels[c]));
  }
  return result;
}

}  // namespace koma

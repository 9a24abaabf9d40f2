#include "core/lip_blink_grid.h"

#include <algorithm>
#include <cmath>

#include "core/curve_cursor.h"
#include "core/lip_blink_internal.h"

namespace koma {

std::vector<double> SampleOnGrid(const Curve& curve, const FilmGrid& grid, int grid_frames,
                                 bool beziers_restricted) {
  std::vector<double> values(static_cast<size_t>(grid_frames));
  CurveCursor cursor(curve, beziers_restricted);  // times only grow: it walks forward
  for (int g = 0; g < grid_frames; ++g) values[g] = cursor.Evaluate(grid.SourceTime(g));
  return values;
}

std::vector<FrameInterval> IntervalsOnGrid(const std::vector<FrameInterval>& intervals,
                                           const FilmGrid& grid, int grid_frames) {
  std::vector<FrameInterval> out;
  for (const FrameInterval& in : intervals) {
    const int begin = std::min(grid.NearestGridFrame(in.begin), grid_frames);
    const int end = std::min(grid.NearestGridFrame(in.end), grid_frames);
    if (end > begin) out.push_back({begin, end});
  }
  return out;
}

std::vector<bool> SpeechMask(const std::vector<FrameInterval>& speech, int grid_frames) {
  std::vector<bool> mask(static_cast<size_t>(grid_frames), false);
  for (const FrameInterval& i : speech) {
    std::fill(mask.begin() + i.begin, mask.begin() + i.end, true);
  }
  return mask;
}

std::vector<bool> BlinkMask(const std::vector<Blink>& blinks, int grid_frames) {
  std::vector<bool> mask(static_cast<size_t>(grid_frames), false);
  const std::vector<int> ends = lip_blink_internal::PaintEnds(blinks, grid_frames);
  for (size_t i = 0; i < blinks.size(); ++i) {
    std::fill(mask.begin() + blinks[i].closing_begin, mask.begin() + ends[i], true);
  }
  return mask;
}

namespace {

// The grid frame just before a repainted run shows its grid value too: the source frames
// there lie between the last grid sample the conversion saw as untouched and the run, and
// their own values (an eye already half shut, say) are the in-between drawing the
// conversion removed.
std::vector<bool> WithFrameBefore(const std::vector<bool>& repainted_runs) {
  std::vector<bool> repainted = repainted_runs;
  for (size_t g = 0; g + 1 < repainted_runs.size(); ++g) {
    if (repainted_runs[g + 1]) repainted[g] = true;
  }
  return repainted;
}

}  // namespace

std::vector<bool> RepaintedSourceFrames(const std::vector<bool>& repainted_runs,
                                        const FilmGrid& grid, int frames) {
  const std::vector<bool> repainted = WithFrameBefore(repainted_runs);
  const int grid_frames = static_cast<int>(repainted.size());
  std::vector<bool> out(static_cast<size_t>(frames));
  for (int k = 0; k < frames; ++k) out[k] = repainted[std::min(grid.GridFrameOf(k), grid_frames - 1)];
  return out;
}

std::vector<double> HeldBetweenRepaints(const std::vector<double>& source,
                                        const std::vector<double>& tau,
                                        const std::vector<bool>& repainted) {
  const int frames = static_cast<int>(source.size());
  std::vector<double> out(static_cast<size_t>(frames), 0.0);
  for (int k = 0; k < frames;) {
    if (repainted[k]) {
      ++k;
      continue;
    }
    int end = k;  // the run of frames no conversion repainted: [k, end)
    while (end < frames && !repainted[end]) ++end;
    for (int f = k; f < end; ++f) {
      // The nearest source frame (ties to the later), kept inside the run.
      const double nearest = std::floor(tau[f] + 0.5);
      const int from = nearest <= k ? k : (nearest >= end - 1 ? end - 1 : static_cast<int>(nearest));
      out[f] = source[from];
    }
    k = end;
  }
  return out;
}

SourceRateCurve ExpandConverted(const std::vector<double>& grid_values,
                                const std::vector<bool>& repainted_runs,
                                const std::vector<double>& source_values, const FilmGrid& grid) {
  SourceRateCurve out;
  const int frames = static_cast<int>(source_values.size());
  const int grid_frames = static_cast<int>(grid_values.size());
  const std::vector<bool> repainted = WithFrameBefore(repainted_runs);
  const auto grid_of = [&](int k) { return std::min(grid.GridFrameOf(k), grid_frames - 1); };
  out.values.resize(static_cast<size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    const int g = grid_of(k);
    out.values[k] = repainted[g] ? grid_values[g] : source_values[k];
  }
  // Both clocks in time order: a repainted grid frame changes the value at its own time, a
  // source frame elsewhere at its frame; at equal times the grid frame goes first (the
  // source frame then shows that very grid frame).
  const auto emit = [&out](double frame, double value) {
    if (out.steps.empty() || out.steps.back().value != value) out.steps.push_back({frame, value});
  };
  int k = 0;
  int g = 0;
  while (k < frames) {
    if (g < grid_frames && grid.SourceTime(g) <= k) {
      if (repainted[g]) emit(grid.SourceTime(g), grid_values[g]);
      ++g;
      continue;
    }
    if (!repainted[grid_of(k)]) emit(k, source_values[k]);
    ++k;
  }
  const double last = static_cast<double>(frames - 1);
  if (out.steps.back().frame < last) out.steps.push_back({last, out.steps.back().value});
  return out;
}

}  // namespace koma

// RetimeNaive: the steps of docs/semantics.md, "RetimeSkeletal", literally. Every step
// recomputes SSD(t) over the whole current sequence and rescans all candidates:
// O((omissions + holds) * N * J). It is the reference RetimeFast is tested against, so clarity
// beats speed here.
#include <cstdint>
#include <utility>
#include <vector>

#include "core/retime.h"
#include "core/retime_internal.h"

namespace koma {
namespace {

using retime_internal::Step;

struct Sequence {
  std::vector<int32_t> source;  // S: output frame t shows source frame source[t]
  std::vector<FrameKind> kinds;
};

// SSD(t) = dist(S[t-1], S[t]) for every t >= 1 of the current sequence; ssd[0] = 0.
std::vector<double> CurrentSsd(const FrameDistance& distance, const Sequence& s) {
  std::vector<double> ssd(s.source.size(), 0.0);
  for (size_t t = 1; t < s.source.size(); ++t) ssd[t] = distance(s.source[t - 1], s.source[t]);
  return ssd;
}

// run(t): the length of the maximal block of equal source indices containing t.
int RunLength(const Sequence& s, int t) {
  int first = t;
  int last = t;
  while (first > 0 && s.source[first - 1] == s.source[t]) --first;
  while (last + 1 < static_cast<int>(s.source.size()) && s.source[last + 1] == s.source[t]) {
    ++last;
  }
  return last - first + 1;
}

bool StillShown(const Sequence& s, int32_t frame) {
  for (int32_t shown : s.source) {
    if (shown == frame) return true;
  }
  return false;
}

// Step A.1. Returns false (and changes nothing) when every candidate has SSD 0.
bool DeleteFastestFrame(const FrameDistance& distance, Sequence& s, std::vector<Step>& gone_in,
                        TimingMap& map) {
  const int len = static_cast<int>(s.source.size());
  const std::vector<double> ssd = CurrentSsd(distance, s);
  int best = -1;
  for (int t = 1; t <= len - 2; ++t) {
    if (best < 0 || ssd[t] > ssd[best]) best = t;  // strict: ties keep the smallest t
  }
  if (best < 0 || ssd[best] == 0.0) return false;
  const int32_t removed = s.source[best];
  if (s.kinds[best] == FrameKind::kDuplicate) ++map.duplicates_omitted;
  s.source.erase(s.source.begin() + best);
  s.kinds.erase(s.kinds.begin() + best);
  if (!StillShown(s, removed)) gone_in[removed] = Step::kOmit;
  return true;
}

// Step A.2. Returns false when no gap qualifies.
bool DuplicateStillestGap(const FrameDistance& distance, const RetimeOptions& options,
                          Sequence& s) {
  const int len = static_cast<int>(s.source.size());
  const std::vector<double> ssd = CurrentSsd(distance, s);
  int best = -1;
  for (int t = 1; t <= len - 1; ++t) {
    if (RunLength(s, t - 1) >= options.max_hold) continue;
    if (best < 0 || ssd[t] < ssd[best]) best = t;
  }
  if (best < 0) return false;
  s.source.insert(s.source.begin() + best, s.source[best - 1]);
  s.kinds.insert(s.kinds.begin() + best, FrameKind::kDuplicate);
  return true;
}

// Step B, once. Returns false when no candidate remains.
bool HoldStillestFrame(const FrameDistance& distance, const RetimeOptions& options, Sequence& s,
                       std::vector<Step>& gone_in, TimingMap& map) {
  const int len = static_cast<int>(s.source.size());
  const std::vector<double> ssd = CurrentSsd(distance, s);
  int best = -1;
  for (int t = 1; t <= len - 2; ++t) {
    if (s.source[t] == s.source[t - 1]) continue;
    if (RunLength(s, t - 1) + 1 > options.max_hold) continue;
    if (best < 0 || ssd[t] < ssd[best]) best = t;
  }
  if (best < 0) return false;
  const int32_t overwritten = s.source[best];
  if (s.kinds[best] == FrameKind::kDuplicate) ++map.duplicates_held;
  s.source[best] = s.source[best - 1];
  s.kinds[best] = FrameKind::kHeld;
  if (!StillShown(s, overwritten)) gone_in[overwritten] = Step::kHold;
  return true;
}

void RunOmissions(const FrameDistance& distance, const RetimeOptions& options, Sequence& s,
                  std::vector<Step>& gone_in, TimingMap& map) {
  for (int i = 0; i < options.omissions; ++i) {
    if (!DeleteFastestFrame(distance, s, gone_in, map)) return;  // nothing moves: stop step A
    ++map.omissions_applied;
    if (!options.keep_length) continue;
    if (DuplicateStillestGap(distance, options, s)) {
      ++map.duplicates_applied;
    } else {
      ++map.duplicates_skipped;
    }
  }
}

// The drawings the sequence shows: its runs.
int CountRuns(const Sequence& s) {
  int runs = 0;
  for (size_t t = 0; t < s.source.size(); ++t) runs += t == 0 || s.source[t] != s.source[t - 1];
  return runs;
}

void RunHolds(const FrameDistance& distance, const RetimeOptions& options, Sequence& s,
              std::vector<Step>& gone_in, TimingMap& map) {
  for (int i = 0; i < options.holds; ++i) {
    if (options.max_drawings > 0 && CountRuns(s) <= options.max_drawings) return;
    if (!HoldStillestFrame(distance, options, s, gone_in, map)) return;
    ++map.holds_applied;
  }
}

}  // namespace

TimingMap RetimeNaive(const FrameDistance& distance, const RetimeOptions& options) {
  const int n = distance.frame_count();
  Sequence s;
  for (int k = 0; k < n; ++k) {
    s.source.push_back(k);
    s.kinds.push_back(FrameKind::kOriginal);
  }
  std::vector<Step> gone_in(n, Step::kNone);
  TimingMap map;
  for (Step step : retime_internal::StepsInOrder(options.order)) {
    if (step == Step::kOmit) RunOmissions(distance, options, s, gone_in, map);
    if (step == Step::kHold) RunHolds(distance, options, s, gone_in, map);
  }
  map.source_frames = std::move(s.source);
  map.kinds = std::move(s.kinds);
  retime_internal::FillGoneFrames(gone_in, map);
  return map;
}

}  // namespace koma

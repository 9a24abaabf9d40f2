// RetimeFast: the same results as RetimeNaive in O(N*J + (omissions + holds) * (J + log N)).
//
// Why it works. The working sequence S is always non-decreasing: a delete removes an
// element, a duplicate copies S[t-1] right after it, a hold copies the predecessor's value.
// So all output frames showing source frame v form ONE contiguous run, named by v, and
// runs keep their order. SSD inside a run is exactly 0 (dist(v, v) = 0); only a run's head
// (its first frame) can have a non-zero SSD: head_ssd = dist(previous run's v, v). Output
// position order is (v of the run, rank inside it), and every candidate below sits at rank
// 0 (a head) or 1, so "ties go to the smallest t" compares position = 2 * v + rank.
//
// A run's kinds are always [front, kDuplicate x duplicates, kHeld x helds]: a run starts as
// [kOriginal]; a duplicate is inserted at index 1, before every other D and H; a hold
// appends kHeld at the back of the previous run; a delete or a hold pops the front, whose
// successor (the first D, else the first H) becomes the front. So three numbers store it.
//
// Candidates per run, each kept in a heap with lazy invalidation (see CandidateHeap):
//  - delete (step A.1): an interior head (not the first run; not the last output frame),
//    key (head_ssd, largest first; position). Frames at rank >= 1 have SSD 0, so when the
//    best head has SSD 0, every candidate has: stop step A.
//  - duplicate (A.2), when length < max_hold: if length >= 2 the gap after the front
//    (SSD 0, position 2v + 1), which beats every other gap of the run; else the gap before
//    the next run's head (next's head_ssd, position 2 * next + 0).
//  - hold (B): an interior head whose previous run is shorter than max_hold, key
//    (head_ssd, smallest first; position).
// Each run has at most one current candidate per heap, and the heaps order ties by the run v
// instead of the position: for delete and hold candidates position = 2v; a duplicate
// candidate of run v sits in (2v, 2 * next(v)], so between current candidates of different
// runs the two orders agree.
//
// Lazy invalidation without versions: an entry {ssd, v} is current when run v is alive and
// its candidate, recomputed from the run now, exists with that same ssd (equal keys mean an
// equal place in the order, so an old entry that happens to match is as good as a fresh
// one). Every edit pushes a fresh entry for each run whose candidate may have changed or
// reappeared, and nothing else; a candidate that only disappears needs no push.
//
// Cost: the N - 1 distances of the input SSD, one distance per unlinked run, and the queue
// work. Where the memory traffic goes at 1M frames, and what keeps it down:
//  - Step A pops at most a few thousand entries, so its two heaps are loaded with only about
//    the best 4 * Nio candidates (a bound from a sample of every 64th run); if the best entry
//    ever falls behind the bound, that heap is reloaded from every live run (LoadOmitHeap).
//  - Step B takes ~N/3 holds from the bottom of ~N candidates: a SortedCandidateQueue
//    buckets them once by SSD and sorts a bucket only when reading reaches it, so the holds
//    read an array front to back instead of sifting a heap of N entries down each time.
//  - A hold usually unlinks a run v whose neighbours are v - 1 and v + 1 (or v + 2): the
//    distances dist(v - 1, v + 1) and dist(v - 1, v + 2) come from tables computed in the same
//    streaming pass as the input SSD (FrameDistance::AdjacentDistances, bit-identical to
//    operator()), not from two random 744-byte frames.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/large_array.h"
#include "core/retime.h"
#include "core/retime_candidates.h"
#include "core/retime_internal.h"
#include "core/stop_check.h"

namespace koma {
namespace {

using retime_internal::CandidateEntry;
using retime_internal::CandidateHeap;
using retime_internal::SortedCandidateQueue;
using retime_internal::Step;

constexpr int32_t kNoRun = -1;
constexpr int32_t kTableMinFrames = 50000;  // see the FastRetimer constructor
constexpr size_t kPrefetchAhead = 16;       // hold candidates; see BestHold

struct Run {
  int32_t prev = kNoRun;  // neighbouring runs (their source frames), kNoRun at the ends
  int32_t next = kNoRun;
  double head_ssd = 0.0;   // dist(prev, this): the SSD at this run's first frame
  int32_t duplicates = 0;  // kDuplicate frames right after the front
  int32_t helds = 0;       // kHeld frames after those
  FrameKind front = FrameKind::kOriginal;
  bool alive = true;

  int32_t Length() const { return 1 + duplicates + helds; }
};

class FastRetimer {
 public:
  // Stores the input's per-frame SSD in `input_ssd` if not null; `known_ssd`, when not null,
  // holds it already (RetimeInputSsd's) and is moved from instead of computed. Tables for
  // step B from `table_min_frames` frames on (kTableMinFrames but in tests).
  FastRetimer(const FrameDistance& distance, const RetimeOptions& options,
              std::vector<double>* input_ssd, int table_min_frames, std::vector<double>* known_ssd);

  void RunOmissions(TimingMap& map);
  void RunHolds(TimingMap& map);
  // Writes the sequence and the gone frames into `map`.
  void Finish(TimingMap& map) const;

 private:
  bool IsInteriorHead(const Run& run) const {
    return run.prev != kNoRun && !(run.next == kNoRun && run.Length() == 1);
  }
  // The current candidates of run v (false: none); `ssd` gets the key.
  bool DeleteKey(const Run& run, double& ssd) const {
    if (!IsInteriorHead(run)) return false;
    ssd = run.head_ssd;
    return true;
  }
  bool DuplicateKey(const Run& run, double& ssd) const {
    const int32_t length = run.Length();
    if (length >= options_.max_hold) return false;
    if (length >= 2) {
      ssd = 0.0;
      return true;
    }
    if (run.next == kNoRun) return false;  // the gap after the last frame is not a gap
    ssd = runs_[run.next].head_ssd;
    return true;
  }
  bool HoldKey(const Run& run, double& ssd) const {
    if (!IsInteriorHead(run)) return false;
    if (runs_[run.prev].Length() + 1 > options_.max_hold) return false;
    ssd = run.head_ssd;
    return true;
  }

  // Pushes run v's current candidates into the heaps of the running step.
  void PushOmitEntries(int32_t v);
  void PushHoldEntry(int32_t v);
  void StartStep(Step step);
  // Removes run v's first frame; unlinks the run (recording `step`) if it empties.
  // Returns the kind the popped frame had (kDuplicate: a duplicate omitted or held over).
  FrameKind PopFront(int32_t v, Step step);

  // Step A's heaps are loaded with a bound (see LoadOmitHeap); when the best entry is not
  // trusted, the heap is reloaded from every live run without one.
  const CandidateEntry* BestDelete() {
    auto current = [this](const CandidateEntry& entry) {
      const Run& run = runs_[entry.run];
      double ssd;
      return run.alive && DeleteKey(run, ssd) && ssd == entry.ssd;
    };
    const CandidateEntry* best = delete_heap_.Top(current);
    if (delete_heap_.Trusted(best)) return best;
    LoadOmitHeap(delete_heap_, false, 0);
    return delete_heap_.Top(current);
  }
  const CandidateEntry* BestDuplicate() {
    auto current = [this](const CandidateEntry& entry) {
      const Run& run = runs_[entry.run];
      double ssd;
      return run.alive && DuplicateKey(run, ssd) && ssd == entry.ssd;
    };
    const CandidateEntry* best = duplicate_heap_.Top(current);
    if (duplicate_heap_.Trusted(best)) return best;
    LoadOmitHeap(duplicate_heap_, true, 0);
    return duplicate_heap_.Top(current);
  }
  // Loads `heap` (the delete heap, or the duplicate heap if `duplicates`) with the current
  // candidates of every live run. With pops > 0 only about the best 4 * pops of them: a
  // bound is taken from a sample of every 64th run, and the rest are left out (see
  // CandidateHeap::SetBound). Step A pops at most a few thousand entries, so building two
  // heaps of N entries would cost far more than it ever reads.
  void LoadOmitHeap(CandidateHeap& heap, bool duplicates, int64_t pops);
  const CandidateEntry* BestHold() {
    // The candidates read next are random runs of a table too large for the caches: start
    // loading the lines a hold kPrefetchAhead reads later will touch (its run, its
    // neighbours, the tables' entries for its unlink), so the misses overlap.
    if (const CandidateEntry* ahead = hold_heap_.Ahead(kPrefetchAhead)) {
      const size_t v = ahead->run;  // an interior head: 1 <= v < N
      __builtin_prefetch(&runs_[v - 1]);
      __builtin_prefetch(&runs_[v]);
      if (v + 1 < runs_.size()) __builtin_prefetch(&runs_[v + 1]);
      if (!skip_.empty()) {
        __builtin_prefetch(&skip_[v]);
        __builtin_prefetch(&skip2_[v]);
      }
    }
    return hold_heap_.Top([this](const CandidateEntry& entry) {
      const Run& run = runs_[entry.run];
      double ssd;
      return run.alive && HoldKey(run, ssd) && ssd == entry.ssd;
    });
  }

  // dist(prev, next), from the tables when they hold it (step B's usual unlinks: next is 2
  // or 3 frames after prev).
  double NewHeadSsd(int32_t prev, int32_t next) const {
    if (!skip_.empty()) {
      if (next == prev + 2) return skip_[prev + 1];
      if (next == prev + 3) return skip2_[prev + 1];
    }
    return distance_(prev, next);
  }

  const FrameDistance& distance_;
  const RetimeOptions& options_;
  // The large arrays (core/large_array.h: huge pages in koma_server).
  LargeArray<Run> runs_;       // indexed by source frame; run 0 is always first
  std::vector<Step> gone_in_;  // per source frame: the step that removed it
  // When holds run (else empty): skip_[v] = dist(v - 1, v + 1), skip2_[v] = dist(v - 1, v + 2).
  LargeArray<double> skip_;
  LargeArray<double> skip2_;
  CandidateHeap delete_heap_{true};  // largest SSD first
  CandidateHeap duplicate_heap_{false};
  SortedCandidateQueue hold_heap_;
  int32_t live_runs_ = 0;  // runs alive: the drawings the sequence shows (max_drawings)
};

FastRetimer::FastRetimer(const FrameDistance& distance, const RetimeOptions& options,
                         std::vector<double>* input_ssd, int table_min_frames,
                         std::vector<double>* known_ssd)
    : distance_(distance),
      options_(options),
      runs_(distance.frame_count()),
      gone_in_(distance.frame_count(), Step::kNone) {
  const int32_t n = distance.frame_count();
  live_runs_ = n;
  for (int32_t v = 0; v < n; ++v) {
    runs_[v].prev = v - 1;
    runs_[v].next = v + 1 < n ? v + 1 : kNoRun;
  }
  if (n >= table_min_frames && int64_t{4} * options.holds >= n) {
    // Step B usually unlinks a run v between v - 1 and v + 1 or v + 2: skip_ and skip2_ have
    // those distances, computed in the same streaming pass as the input SSD. They cost two
    // more distances per frame, so only where they replace enough random reads: many holds
    // (>= N/4) on a clip too large for the cache.
    LargeArray<double> ssd;
    distance_.AdjacentDistances(&ssd, &skip_, &skip2_);
    for (int32_t v = 1; v < n; ++v) runs_[v].head_ssd = ssd[v];
    if (input_ssd != nullptr) input_ssd->assign(ssd.begin(), ssd.end());
  } else {
    std::vector<double> ssd =
        known_ssd != nullptr ? std::move(*known_ssd) : RetimeInputSsd(distance_);
    for (int32_t v = 1; v < n; ++v) runs_[v].head_ssd = ssd[v];
    if (input_ssd != nullptr) *input_ssd = std::move(ssd);
  }
}

void FastRetimer::PushOmitEntries(int32_t v) {
  if (v == kNoRun) return;
  const Run& run = runs_[v];
  if (!run.alive) return;
  double ssd;
  if (DeleteKey(run, ssd)) delete_heap_.Push({ssd, static_cast<uint32_t>(v)});
  if (options_.keep_length && DuplicateKey(run, ssd)) {
    duplicate_heap_.Push({ssd, static_cast<uint32_t>(v)});
  }
}

void FastRetimer::PushHoldEntry(int32_t v) {
  if (v == kNoRun) return;
  const Run& run = runs_[v];
  double ssd;
  if (run.alive && HoldKey(run, ssd)) hold_heap_.Push({ssd, static_cast<uint32_t>(v)});
}

// Only the running step's heaps are maintained: each step starts by rebuilding them from
// every live run in O(N), so the other step's edits need no bookkeeping.
void FastRetimer::StartStep(Step step) {
  delete_heap_.Clear();
  duplicate_heap_.Clear();
  hold_heap_.Clear();
  if (step == Step::kOmit) {
    LoadOmitHeap(delete_heap_, false, options_.omissions);
    if (options_.keep_length) LoadOmitHeap(duplicate_heap_, true, options_.omissions);
  } else {
    // At most one entry per run (later pushes go to the queue's own heap).
    hold_heap_.StartBulkLoad(runs_.size());
    for (int32_t v = 0; v != kNoRun; v = runs_[v].next) PushHoldEntry(v);
    hold_heap_.Heapify();
  }
}

void FastRetimer::LoadOmitHeap(CandidateHeap& heap, bool duplicates, int64_t pops) {
  auto key = [this, duplicates](const Run& run, double& ssd) {
    return duplicates ? DuplicateKey(run, ssd) : DeleteKey(run, ssd);
  };
  heap.Clear();
  // Room for the pushes of step A after the load: three per delete and three per duplicate
  // (RunOmissions), so a Pitch-size clip's heaps take a few KB, not 64 KB each.
  const size_t pushes = 6 * static_cast<size_t>(std::max(options_.omissions, 0));
  bool bounded = false;
  constexpr size_t kSampleStride = 64;
  const size_t rank = pops > 0 ? static_cast<size_t>(4 * pops) / kSampleStride + 16 : 0;
  if (pops > 0 && runs_.size() / kSampleStride > 4 * rank) {
    std::vector<CandidateEntry> sample;
    sample.reserve(runs_.size() / kSampleStride + 1);
    for (size_t v = 0; v < runs_.size(); v += kSampleStride) {
      double ssd;
      if (runs_[v].alive && key(runs_[v], ssd)) sample.push_back({ssd, static_cast<uint32_t>(v)});
    }
    if (sample.size() > rank) {
      auto before = [&heap](const CandidateEntry& a, const CandidateEntry& b) {
        return heap.Before(a, b);
      };
      std::nth_element(sample.begin(), sample.begin() + rank, sample.end(), before);
      heap.StartBulkLoad(8 * rank * kSampleStride + pushes);
      heap.SetBound(sample[rank]);
      bounded = true;
    }
  }
  // No bound: room for every run.
  if (!bounded) heap.StartBulkLoad(runs_.size() + pushes);
  for (int32_t v = 0; v != kNoRun; v = runs_[v].next) {
    double ssd;
    if (key(runs_[v], ssd)) heap.Push({ssd, static_cast<uint32_t>(v)});
  }
  heap.Heapify();
}

FrameKind FastRetimer::PopFront(int32_t v, Step step) {
  Run& run = runs_[v];
  const FrameKind popped = run.front;
  if (run.duplicates > 0) {
    run.front = FrameKind::kDuplicate;
    --run.duplicates;
    return popped;
  }
  if (run.helds > 0) {
    run.front = FrameKind::kHeld;
    --run.helds;
    return popped;
  }
  // The run empties: source frame v is no longer shown. v is never the first run (only
  // interior heads are edited), so prev exists; the new head of next is next itself.
  run.alive = false;
  --live_runs_;
  gone_in_[v] = step;
  runs_[run.prev].next = run.next;
  if (run.next != kNoRun) {
    runs_[run.next].prev = run.prev;
    runs_[run.next].head_ssd = NewHeadSsd(run.prev, run.next);
  }
  return popped;
}

// After an edit of run v (prev and next are its neighbours BEFORE the edit), the candidates
// that can change are those of prev, v and next, and no others:
//  - a run's delete/hold candidate reads its own length, head_ssd and neighbours, and (hold)
//    its previous run's length; a run's duplicate candidate reads its own length and its next
//    run's v and head_ssd.
//  - a delete or a hold changes the length of v (and, for a hold, of prev); if v empties,
//    it relinks prev <-> next and changes next's head_ssd; a duplicate changes v's length.
//    v's head_ssd never changes while v lives (its new front still follows prev).
// Step A has few steps, so it pushes for all three. Step B pushes only what can change or
// reappear (see RunHolds).
void FastRetimer::RunOmissions(TimingMap& map) {
  if (options_.omissions <= 0) return;
  StartStep(Step::kOmit);
  StopPoll stop;  // a stopped call's map is discarded by whoever installed the signal
  for (int i = 0; i < options_.omissions; ++i) {
    if (stop.Stop()) return;
    const CandidateEntry* best = BestDelete();
    if (best == nullptr || best->ssd == 0.0) return;  // nothing moves: stop step A
    const int32_t v = static_cast<int32_t>(best->run);
    const int32_t prev = runs_[v].prev;
    const int32_t next = runs_[v].next;
    if (PopFront(v, Step::kOmit) == FrameKind::kDuplicate) ++map.duplicates_omitted;
    PushOmitEntries(prev);
    PushOmitEntries(v);
    PushOmitEntries(next);
    ++map.omissions_applied;
    if (!options_.keep_length) continue;
    const CandidateEntry* gap = BestDuplicate();
    if (gap == nullptr) {
      ++map.duplicates_skipped;
      continue;
    }
    const int32_t into = static_cast<int32_t>(gap->run);  // gets the copy after its front
    ++runs_[into].duplicates;
    PushOmitEntries(runs_[into].prev);
    PushOmitEntries(into);
    PushOmitEntries(runs_[into].next);
    ++map.duplicates_applied;
  }
}

// A hold at v (previous run prev, next run next) lengthens prev and shortens v:
//  - prev's own candidate reads prev's head_ssd, its interior-ness (unchanged: prev keeps a
//    successor and grows) and prev's previous run's length: unchanged, no push.
//  - v, if it survives, keeps its head_ssd; only prev's growth can have made it ineligible,
//    which the lazy check sees: no push. If it empties, it is dead.
//  - next's candidate reads its previous run's length (v shrank, or prev grew and became
//    next's previous run) and, after an unlink, its new head_ssd: push it.
void FastRetimer::RunHolds(TimingMap& map) {
  if (options_.holds <= 0) return;
  StartStep(Step::kHold);
  StopPoll stop;  // a stopped call's map is discarded by whoever installed the signal
  for (int i = 0; i < options_.holds; ++i) {
    if (stop.Stop()) return;
    if (options_.max_drawings > 0 && live_runs_ <= options_.max_drawings) return;
    const CandidateEntry* best = BestHold();
    if (best == nullptr) return;  // no candidate remains: stop early
    const int32_t v = static_cast<int32_t>(best->run);
    const int32_t prev = runs_[v].prev;
    const int32_t next = runs_[v].next;
    ++runs_[prev].helds;  // v's first frame now shows prev, at the end of prev's run
    if (PopFront(v, Step::kHold) == FrameKind::kDuplicate) ++map.duplicates_held;
    PushHoldEntry(next);
    ++map.holds_applied;
  }
}

void FastRetimer::Finish(TimingMap& map) const {
  map.source_frames.clear();
  map.kinds.clear();
  map.source_frames.reserve(runs_.size() + options_.omissions);
  map.kinds.reserve(runs_.size() + options_.omissions);
  for (int32_t v = 0; v != kNoRun; v = runs_[v].next) {
    const Run& run = runs_[v];
    map.source_frames.insert(map.source_frames.end(), run.Length(), v);
    map.kinds.push_back(run.front);
    map.kinds.insert(map.kinds.end(), run.duplicates, FrameKind::kDuplicate);
    map.kinds.insert(map.kinds.end(), run.helds, FrameKind::kHeld);
  }
  retime_internal::FillGoneFrames(gone_in_, map);
}

}  // namespace

TimingMap retime_internal::RetimeFastWithTablesFrom(const FrameDistance& distance,
                                                    const RetimeOptions& options,
                                                    std::vector<double>* input_ssd,
                                                    int table_min_frames,
                                                    std::vector<double>* known_ssd) {
  FastRetimer retimer(distance, options, input_ssd, table_min_frames, known_ssd);
  TimingMap map;
  for (Step step : retime_internal::StepsInOrder(options.order)) {
    if (step == Step::kOmit) retimer.RunOmissions(map);
    if (step == Step::kHold) retimer.RunHolds(map);
  }
  retimer.Finish(map);
  return map;
}

TimingMap RetimeFast(const FrameDistance& distance, const RetimeOptions& options,
                     std::vector<double>* input_ssd) {
  return retime_internal::RetimeFastWithTablesFrom(distance, options, input_ssd, kTableMinFrames,
                                                   nullptr);
}

std::vector<double> RetimeInputSsd(const FrameDistance& distance) {
  // Below kTableMinFrames the clip fits the caches (see InputSsdOfSmallClip).
  return distance.frame_count() < kTableMinFrames ? distance.InputSsdOfSmallClip()
                                                  : distance.InputSsd();
}

TimingMap RetimeFastWithInputSsd(const FrameDistance& distance, const RetimeOptions& options,
                                 std::vector<double> ssd, std::vector<double>* input_ssd) {
  return retime_internal::RetimeFastWithTablesFrom(distance, options, input_ssd, kTableMinFrames,
                                                   &ssd);
}

}  // namespace koma

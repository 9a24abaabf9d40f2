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
// Candidates per run, each kept in a max-heap with lazy invalidation (see CandidateHeap):
//  - delete (step A.1): an interior head (not the first run; not the last output frame),
//    key (head_ssd, largest first; position). Frames at rank >= 1 have SSD 0, so when the
//    best head has SSD 0, every candidate has: stop step A.
//  - duplicate (A.2), when length < max_hold: if length >= 2 the gap after the front
//    (SSD 0, position 2v + 1), which beats every other gap of the run; else the gap before
//    the next run's head (next's head_ssd, position 2 * next + 0).
//  - hold (B): an interior head whose previous run is shorter than max_hold, key
//    (head_ssd, smallest first; position).
#include <cstdint>
#include <vector>

#include "core/retime.h"
#include "core/retime_candidates.h"
#include "core/retime_internal.h"

namespace koma {
namespace {

using retime_internal::CandidateEntry;
using retime_internal::CandidateHeap;
using retime_internal::Step;

constexpr int32_t kNoRun = -1;

struct Run {
  int32_t prev = kNoRun;  // neighbouring runs (their source frames), kNoRun at the ends
  int32_t next = kNoRun;
  double head_ssd = 0.0;  // dist(prev, this): the SSD at this run's first frame
  FrameKind front = FrameKind::kOriginal;
  int32_t duplicates = 0;  // kDuplicate frames right after the front
  int32_t helds = 0;       // kHeld frames after those
  // Bumped by every Refresh (at most twice per step); heap entries with an older version
  // are stale. 64 bits, so it cannot wrap.
  uint64_t version = 0;
  bool alive = true;

  int32_t Length() const { return 1 + duplicates + helds; }
};

class FastRetimer {
 public:
  FastRetimer(const FrameDistance& distance, const RetimeOptions& options);

  void RunOmissions(TimingMap& map);
  void RunHolds(TimingMap& map);
  // Writes the sequence and the gone frames into `map`.
  void Finish(TimingMap& map) const;

 private:
  bool IsInteriorHead(int32_t v) const {
    const Run& run = runs_[v];
    return run.prev != kNoRun && !(run.next == kNoRun && run.Length() == 1);
  }
  bool DeleteEntry(int32_t v, CandidateEntry& entry) const;
  bool DuplicateEntry(int32_t v, CandidateEntry& entry) const;
  bool HoldEntry(int32_t v, CandidateEntry& entry) const;
  // Pushes the current entries of run v into the heaps of the step now running.
  void PushEntries(int32_t v);
  // Invalidates run v's entries and pushes fresh ones.
  void Refresh(int32_t v);
  void StartStep(Step step);
  // Removes run v's first frame; unlinks the run (recording `step`) if it empties.
  void PopFront(int32_t v, Step step);
  void RefreshAround(int32_t prev, int32_t v, int32_t next);
  // The best current entry of `heap`, or nullptr.
  const CandidateEntry* Best(CandidateHeap& heap) const {
    return heap.Top([this](const CandidateEntry& entry) {
      const Run& run = runs_[entry.run];
      return run.alive && run.version == entry.version;
    });
  }

  const FrameDistance& distance_;
  const RetimeOptions& options_;
  std::vector<Run> runs_;            // indexed by source frame; run 0 is always first
  std::vector<Step> gone_in_;        // per source frame: the step that removed it
  Step active_ = Step::kNone;        // the step whose heaps are maintained
  CandidateHeap delete_heap_{true};  // largest SSD first
  CandidateHeap duplicate_heap_{false};
  CandidateHeap hold_heap_{false};
};

FastRetimer::FastRetimer(const FrameDistance& distance, const RetimeOptions& options)
    : distance_(distance),
      options_(options),
      runs_(distance.frame_count()),
      gone_in_(distance.frame_count(), Step::kNone) {
  const int32_t n = distance.frame_count();
  for (int32_t v = 0; v < n; ++v) {
    runs_[v].prev = v - 1;
    runs_[v].next = v + 1 < n ? v + 1 : kNoRun;
    if (v > 0) runs_[v].head_ssd = distance_(v - 1, v);
  }
}

bool FastRetimer::DeleteEntry(int32_t v, CandidateEntry& entry) const {
  if (!IsInteriorHead(v)) return false;
  entry = {runs_[v].head_ssd, 2 * static_cast<uint32_t>(v), v, runs_[v].version};
  return true;
}

bool FastRetimer::DuplicateEntry(int32_t v, CandidateEntry& entry) const {
  const Run& run = runs_[v];
  if (run.Length() >= options_.max_hold) return false;
  if (run.Length() >= 2) {
    entry = {0.0, 2 * static_cast<uint32_t>(v) + 1, v, run.version};
    return true;
  }
  if (run.next == kNoRun) return false;  // the gap after the last frame is not a gap
  entry = {runs_[run.next].head_ssd, 2 * static_cast<uint32_t>(run.next), v, run.version};
  return true;
}

bool FastRetimer::HoldEntry(int32_t v, CandidateEntry& entry) const {
  if (!IsInteriorHead(v)) return false;
  if (runs_[runs_[v].prev].Length() + 1 > options_.max_hold) return false;
  entry = {runs_[v].head_ssd, 2 * static_cast<uint32_t>(v), v, runs_[v].version};
  return true;
}

void FastRetimer::PushEntries(int32_t v) {
  CandidateEntry entry;
  if (active_ == Step::kOmit) {
    if (DeleteEntry(v, entry)) delete_heap_.Push(entry);
    if (options_.keep_length && DuplicateEntry(v, entry)) duplicate_heap_.Push(entry);
  } else if (active_ == Step::kHold) {
    if (HoldEntry(v, entry)) hold_heap_.Push(entry);
  }
}

void FastRetimer::Refresh(int32_t v) {
  if (v == kNoRun || !runs_[v].alive) return;
  ++runs_[v].version;
  PushEntries(v);
}

// Only the running step's heaps are maintained: each step starts by rebuilding them from
// every live run in O(N), so the other step's edits need no bookkeeping.
void FastRetimer::StartStep(Step step) {
  active_ = step;
  // At most one entry per run and heap, plus room for the pushes of a few hundred steps.
  const size_t expected = runs_.size() + 1024;
  delete_heap_.StartBulkLoad(step == Step::kOmit ? expected : 0);
  duplicate_heap_.StartBulkLoad(step == Step::kOmit && options_.keep_length ? expected : 0);
  hold_heap_.StartBulkLoad(step == Step::kHold ? expected : 0);
  for (int32_t v = 0; v != kNoRun; v = runs_[v].next) PushEntries(v);
  delete_heap_.Heapify();
  duplicate_heap_.Heapify();
  hold_heap_.Heapify();
}

void FastRetimer::PopFront(int32_t v, Step step) {
  Run& run = runs_[v];
  if (run.duplicates > 0) {
    run.front = FrameKind::kDuplicate;
    --run.duplicates;
    return;
  }
  if (run.helds > 0) {
    run.front = FrameKind::kHeld;
    --run.helds;
    return;
  }
  // The run empties: source frame v is no longer shown. v is never the first run (only
  // interior heads are edited), so prev exists; the new head of next is next itself.
  run.alive = false;
  gone_in_[v] = step;
  runs_[run.prev].next = run.next;
  if (run.next != kNoRun) {
    runs_[run.next].prev = run.prev;
    runs_[run.next].head_ssd = distance_(run.prev, run.next);
  }
}

// After an edit of run v (prev and next are its neighbours BEFORE the edit), the entries
// that can change are those of prev, v and next, and no others:
//  - a run's delete/hold entry reads its own length, head_ssd and neighbours, and (hold)
//    its previous run's length; a run's duplicate entry reads its own length and its next
//    run's v and head_ssd.
//  - a delete or a hold changes the length of v (and, for a hold, of prev); if v empties,
//    it relinks prev <-> next and changes next's head_ssd; a duplicate changes v's length.
//    v's head_ssd never changes while v lives (its new front still follows prev).
//  So the readers of what changed are prev, v and next (next reads v's length and, after an
//  unlink, its new prev); next's next reads next's length, which did not change.
void FastRetimer::RefreshAround(int32_t prev, int32_t v, int32_t next) {
  Refresh(prev);
  Refresh(v);
  Refresh(next);
}

void FastRetimer::RunOmissions(TimingMap& map) {
  StartStep(Step::kOmit);
  for (int i = 0; i < options_.omissions; ++i) {
    const CandidateEntry* best = Best(delete_heap_);
    if (best == nullptr || best->ssd == 0.0) return;  // nothing moves: stop step A
    const int32_t v = best->run;
    const int32_t prev = runs_[v].prev;
    const int32_t next = runs_[v].next;
    PopFront(v, Step::kOmit);
    RefreshAround(prev, v, next);
    ++map.omissions_applied;
    if (!options_.keep_length) continue;
    const CandidateEntry* gap = Best(duplicate_heap_);
    if (gap == nullptr) {
      ++map.duplicates_skipped;
      continue;
    }
    const int32_t into = gap->run;  // the run that gets the copy, right after its front
    ++runs_[into].duplicates;
    RefreshAround(runs_[into].prev, into, runs_[into].next);
    ++map.duplicates_applied;
  }
}

void FastRetimer::RunHolds(TimingMap& map) {
  StartStep(Step::kHold);
  for (int i = 0; i < options_.holds; ++i) {
    const CandidateEntry* best = Best(hold_heap_);
    if (best == nullptr) return;  // no candidate remains: stop early
    const int32_t v = best->run;
    const int32_t prev = runs_[v].prev;
    const int32_t next = runs_[v].next;
    ++runs_[prev].helds;  // v's first frame now shows prev, at the end of prev's run
    PopFront(v, Step::kHold);
    RefreshAround(prev, v, next);
    ++map.holds_applied;
  }
}

void FastRetimer::Finish(TimingMap& map) const {
  map.source_frames.clear();
  map.kinds.clear();
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

TimingMap RetimeFast(const FrameDistance& distance, const RetimeOptions& options) {
  FastRetimer retimer(distance, options);
  TimingMap map;
  for (Step step : retime_internal::StepsInOrder(options.order)) {
    if (step == Step::kOmit) retimer.RunOmissions(map);
    if (step == Step::kHold) retimer.RunHolds(map);
  }
  retimer.Finish(map);
  return map;
}

}  // namespace koma

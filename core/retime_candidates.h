// The candidate priority queue of RetimeFast (internal): a 4-ary heap with lazy
// invalidation. Entries are never erased in place; an edit pushes a fresh entry and an old one
// is dropped when it reaches the top and no longer matches its run's current candidate (the
// caller's is_current check recomputes that candidate, so no version counter is stored).
#ifndef KOMA_CORE_RETIME_CANDIDATES_H_
#define KOMA_CORE_RETIME_CANDIDATES_H_

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace koma::retime_internal {

// 16 bytes, so four siblings of the 4-ary heap share one 64-byte cache line.
struct CandidateEntry {
  double ssd = 0.0;  // the SSD at the candidate position
  // The run (its source frame) the candidate belongs to. Among the current candidates of
  // one heap, run order is output position order (see retime_fast.cc), so ties compare it.
  uint32_t run = 0;
  uint32_t unused = 0;
};

class CandidateHeap {
 public:
  // largest_ssd_first: delete candidates; otherwise smallest SSD first. Ties always go to
  // the smallest run (= the smallest output frame index t).
  explicit CandidateHeap(bool largest_ssd_first) : largest_ssd_first_(largest_ssd_first) {}

  // Empties the heap and starts a bulk load of about `expected` entries: Push only
  // appends until Heapify, which orders everything in O(size).
  void StartBulkLoad(size_t expected) {
    entries_.clear();
    entries_.reserve(expected);
    bulk_ = true;
  }
  void Heapify() {
    bulk_ = false;
    const size_t n = entries_.size();
    if (n < 2) return;
    for (size_t i = (n - 2) / kArity + 1; i-- > 0;) SiftDown(i);
  }
  void Clear() {
    entries_.clear();
    bulk_ = false;
  }

  // O(log size), or O(1) during a bulk load.
  void Push(const CandidateEntry& entry) {
    entries_.push_back(entry);
    if (!bulk_) SiftUp(entries_.size() - 1);
  }

  // The best entry for which is_current(entry) holds, dropping stale ones on the way;
  // nullptr when none is left. The pointer is valid until the next Push.
  template <typename IsCurrent>
  const CandidateEntry* Top(IsCurrent is_current) {
    while (!entries_.empty() && !is_current(entries_.front())) PopTop();
    return entries_.empty() ? nullptr : &entries_.front();
  }

 private:
  static constexpr size_t kArity = 4;

  // True when `a` comes out before `b`.
  bool Before(const CandidateEntry& a, const CandidateEntry& b) const {
    if (a.ssd != b.ssd) return largest_ssd_first_ ? a.ssd > b.ssd : a.ssd < b.ssd;
    return a.run < b.run;
  }

  void PopTop() {
    entries_.front() = entries_.back();
    entries_.pop_back();
    if (!entries_.empty()) SiftDown(0);
  }

  void SiftUp(size_t i) {
    const CandidateEntry moving = entries_[i];
    while (i > 0) {
      const size_t parent = (i - 1) / kArity;
      if (!Before(moving, entries_[parent])) break;
      entries_[i] = entries_[parent];
      i = parent;
    }
    entries_[i] = moving;
  }

  void SiftDown(size_t i) {
    const size_t n = entries_.size();
    const CandidateEntry moving = entries_[i];
    for (;;) {
      const size_t first = kArity * i + 1;
      if (first >= n) break;
      const size_t last = first + kArity < n ? first + kArity : n;
      size_t best = first;
      for (size_t c = first + 1; c < last; ++c) {
        if (Before(entries_[c], entries_[best])) best = c;
      }
      if (!Before(entries_[best], moving)) break;
      entries_[i] = entries_[best];
      i = best;
    }
    entries_[i] = moving;
  }

  bool largest_ssd_first_;
  bool bulk_ = false;
  std::vector<CandidateEntry> entries_;
};

}  // namespace koma::retime_internal

#endif  // KOMA_CORE_RETIME_CANDIDATES_H_

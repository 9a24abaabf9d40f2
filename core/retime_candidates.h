// The candidate priority queue of RetimeFast (internal): a 4-ary heap with lazy
// invalidation. Entries are never erased in place; an edit pushes a fresh entry and an old one
// is dropped when it reaches the top and no longer matches its run's current candidate (the
// caller's is_current check recomputes that candidate, so no version counter is stored).
#ifndef KOMA_CORE_RETIME_CANDIDATES_H_
#define KOMA_CORE_RETIME_CANDIDATES_H_

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "core/large_array.h"

namespace koma::retime_internal {

// 16 bytes, so four siblings of the 4-ary heap share one 64-byte cache line.
struct CandidateEntry {
  double ssd = 0.0;  // the SSD at the candidate position
  // The run (its source frame) the candidate belongs to. Among the current candidates of
  // one heap, run order is output position order (see retime_fast.cc), so ties compare it.
  uint32_t run = 0;
  uint32_t unused = 0;
};

// entries.push_back(entry), field by field. A whole-entry copy compiles to one 16-byte load
// of the entry the caller has just built with separate 8- and 4-byte stores, which the CPU
// cannot forward from its store buffer: a stall of about 15 cycles on every push, half the
// time of loading a Pitch-size clip's heaps (perf annotate).
inline void AppendEntry(LargeArray<CandidateEntry>& entries, const CandidateEntry& entry) {
  entries.emplace_back();
  CandidateEntry& slot = entries.back();
  slot.ssd = entry.ssd;
  slot.run = entry.run;
}

class CandidateHeap {
 public:
  // largest_ssd_first: delete candidates; otherwise smallest SSD first. Ties always go to
  // the smallest run (= the smallest output frame index t).
  explicit CandidateHeap(bool largest_ssd_first) : largest_ssd_first_(largest_ssd_first) {}

  // True when `a` comes out before `b`.
  bool Before(const CandidateEntry& a, const CandidateEntry& b) const {
    if (a.ssd != b.ssd) return largest_ssd_first_ ? a.ssd > b.ssd : a.ssd < b.ssd;
    return a.run < b.run;
  }

  // A bounded bulk load: during it, Push keeps only entries that come before `bound`. The
  // caller must then treat a top that does not come before `bound` (or an empty heap) as
  // unknown (see Trusted) and reload without a bound: the entries left out are exactly
  // candidates from the bulk load at or after `bound`, and every later push goes in.
  void SetBound(const CandidateEntry& bound) {
    bound_ = bound;
    bounded_ = true;
  }
  // False when a left-out entry might be the true best: `top` (from Top) is null or not
  // before the bound.
  bool Trusted(const CandidateEntry* top) const {
    return !bounded_ || (top != nullptr && Before(*top, bound_));
  }

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
    bounded_ = false;
  }

  // Drops the top entry (the heap must not be empty).
  void PopTop() {
    entries_.front() = entries_.back();
    entries_.pop_back();
    if (!entries_.empty()) SiftDown(0);
  }

  // O(log size), or O(1) during a bulk load.
  void Push(const CandidateEntry& entry) {
    if (bulk_ && bounded_ && !Before(entry, bound_)) return;
    AppendEntry(entries_, entry);
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
  bool bounded_ = false;
  CandidateEntry bound_;
  LargeArray<CandidateEntry> entries_;
};

// The hold queue of RetimeFast (smallest SSD first, ties to the smallest run): the same
// contract as CandidateHeap, but the bulk-loaded entries are not heapified: one counting pass
// spreads them over up to kMaxBuckets buckets by their SSD (buckets in key order), and a bucket is
// sorted only when the reading reaches it; only entries pushed later live in a heap. Step B
// takes its N/3 holds from the bottom of about N candidates: popping each from a heap of N
// entries costs a sift-down of cache misses, reading sorted buckets front to back costs
// none, and the buckets above the last hold are never sorted. Top merges the two (the
// buckets' head against the heap's top) by the same order.
class SortedCandidateQueue {
 public:
  SortedCandidateQueue() : pushed_(false) {}

  void StartBulkLoad(size_t expected) {
    Clear();
    sorted_.reserve(expected);
    bulk_ = true;
  }
  // Buckets the bulk-loaded entries; later pushes go to the heap.
  void Heapify() {
    bulk_ = false;
    Bucket();
  }
  void Clear() {
    sorted_.clear();
    bucket_end_.clear();
    head_ = 0;
    sorted_end_ = 0;
    bucket_ = 0;
    bulk_ = false;
    pushed_.Clear();
  }

  void Push(const CandidateEntry& entry) {
    if (bulk_) {
      AppendEntry(sorted_, entry);
    } else {
      pushed_.Push(entry);
    }
  }

  // For prefetching only: the bulk-loaded entry `distance` places after the reading position
  // (null past the end; in order within the sorted part, roughly so beyond it).
  const CandidateEntry* Ahead(size_t distance) const {
    return head_ + distance < sorted_.size() ? &sorted_[head_ + distance] : nullptr;
  }

  template <typename IsCurrent>
  const CandidateEntry* Top(IsCurrent is_current) {
    for (;;) {
      if (head_ == sorted_end_ && head_ < sorted_.size()) SortNextBucket();
      const CandidateEntry* heap_top = pushed_.Top([](const CandidateEntry&) { return true; });
      const bool have_sorted = head_ < sorted_.size();
      if (heap_top == nullptr && !have_sorted) return nullptr;
      if (have_sorted && (heap_top == nullptr || Before(sorted_[head_], *heap_top))) {
        if (is_current(sorted_[head_])) return &sorted_[head_];
        ++head_;
      } else {
        if (is_current(*heap_top)) return heap_top;
        pushed_.PopTop();
      }
    }
  }

 private:
  static constexpr uint64_t kMaxBuckets = 4096;

  // A function object rather than a function, so std::sort inlines the comparison.
  struct BeforeOrder {
    bool operator()(const CandidateEntry& a, const CandidateEntry& b) const {
      if (a.ssd != b.ssd) return a.ssd < b.ssd;
      return a.run < b.run;
    }
  };
  static bool Before(const CandidateEntry& a, const CandidateEntry& b) {
    return BeforeOrder()(a, b);
  }
  // Non-negative doubles order like their bit patterns (as unsigned integers); the SSDs are
  // >= 0 and never NaN (-0.0 is read as +0.0).
  static uint64_t Key(const CandidateEntry& e) {
    const double ssd = e.ssd == 0.0 ? 0.0 : e.ssd;
    uint64_t bits;
    std::memcpy(&bits, &ssd, sizeof bits);
    return bits;
  }

  // Buckets by (key - smallest) >> shift_, so keys in bucket b are all below those in b + 1.
  void Bucket() {
    const size_t n = sorted_.size();
    if (n == 0) return;
    uint64_t lo = Key(sorted_[0]);
    uint64_t hi = lo;
    for (const CandidateEntry& e : sorted_) {
      const uint64_t k = Key(e);
      lo = k < lo ? k : lo;
      hi = k > hi ? k : hi;
    }
    // About 64 entries per bucket, at most kMaxBuckets buckets.
    const uint64_t buckets = std::min<uint64_t>(kMaxBuckets, n / 64 + 1);
    int shift = 0;
    while (((hi - lo) >> shift) >= buckets) ++shift;
    std::vector<uint32_t> start(buckets + 1, 0);
    for (const CandidateEntry& e : sorted_) ++start[((Key(e) - lo) >> shift) + 1];
    for (uint64_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    bucket_end_.assign(start.begin() + 1, start.end());
    scratch_.resize(n);
    for (const CandidateEntry& e : sorted_) scratch_[start[(Key(e) - lo) >> shift]++] = e;
    sorted_.swap(scratch_);
    scratch_.clear();
    scratch_.shrink_to_fit();
  }
  void SortNextBucket() {
    while (bucket_ < bucket_end_.size() && bucket_end_[bucket_] <= head_) ++bucket_;
    sorted_end_ = bucket_end_[bucket_];
    std::sort(sorted_.begin() + head_, sorted_.begin() + sorted_end_, BeforeOrder());
  }

  bool bulk_ = false;
  size_t head_ = 0;        // sorted_[head_..] are not yet dropped
  size_t sorted_end_ = 0;  // sorted_[..sorted_end_) are in final order
  size_t bucket_ = 0;      // the bucket being read
  std::vector<uint32_t> bucket_end_;
  LargeArray<CandidateEntry> sorted_;
  LargeArray<CandidateEntry> scratch_;
  CandidateHeap pushed_;
};

}  // namespace koma::retime_internal

#endif  // KOMA_CORE_RETIME_CANDIDATES_H_

// The candidate priority queue of RetimeFast (internal): a binary heap with lazy
// invalidation. Entries are never erased in place; an edit pushes a fresh entry and the old
// one is skipped when it reaches the top (its version no longer matches its run's).
#ifndef KOMA_CORE_RETIME_CANDIDATES_H_
#define KOMA_CORE_RETIME_CANDIDATES_H_

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace koma::retime_internal {

struct CandidateEntry {
  double ssd = 0.0;       // the SSD at the candidate position
  uint32_t position = 0;  // 2 * (source frame of the run holding it) + rank (0 or 1) in it
  int32_t run = 0;        // the run the candidate belongs to (the one an edit changes)
  uint64_t version = 0;   // the run's version when the entry was made
};

class CandidateHeap {
 public:
  // largest_ssd_first: delete candidates; otherwise smallest SSD first. Ties always go to
  // the smallest position (the smallest output frame index t).
  explicit CandidateHeap(bool largest_ssd_first) : largest_ssd_first_(largest_ssd_first) {}

  // Empties the heap and starts a bulk load of about `expected` entries: Push only
  // appends until Heapify, which orders everything in O(size).
  void StartBulkLoad(size_t expected) {
    entries_.clear();
    entries_.reserve(expected);
    bulk_ = true;
  }
  void Heapify() {
    std::make_heap(entries_.begin(), entries_.end(), Lower{largest_ssd_first_});
    bulk_ = false;
  }

  // O(log size), or O(1) during a bulk load.
  void Push(const CandidateEntry& entry) {
    entries_.push_back(entry);
    if (!bulk_) std::push_heap(entries_.begin(), entries_.end(), Lower{largest_ssd_first_});
  }

  // The best entry for which is_current(entry) holds, dropping stale ones on the way;
  // nullptr when none is left. The pointer is valid until the next Push.
  template <typename IsCurrent>
  const CandidateEntry* Top(IsCurrent is_current) {
    while (!entries_.empty() && !is_current(entries_.front())) {
      std::pop_heap(entries_.begin(), entries_.end(), Lower{largest_ssd_first_});
      entries_.pop_back();
    }
    return entries_.empty() ? nullptr : &entries_.front();
  }

 private:
  // Strict weak order for std::*_heap: true when `a` comes out after `b`.
  struct Lower {
    bool largest_ssd_first;
    bool operator()(const CandidateEntry& a, const CandidateEntry& b) const {
      if (a.ssd != b.ssd) return largest_ssd_first ? a.ssd < b.ssd : a.ssd > b.ssd;
      return a.position > b.position;
    }
  };

  bool largest_ssd_first_;
  bool bulk_ = false;
  std::vector<CandidateEntry> entries_;
};

}  // namespace koma::retime_internal

#endif  // KOMA_CORE_RETIME_CANDIDATES_H_

#include "platform/huge_page_pool.h"

#include <sys/mman.h>

#include <cstdint>
#include <mutex>
#include <new>
#include <vector>

namespace koma::platform {
namespace {

struct Mapping {
  void* start;
  size_t length;  // bytes, a multiple of kHugePageBytes
};

// Process-wide: a server's calls run on several threads and free each other's arrays' sizes.
// Calls map a few arrays each, so a mutex and a linear scan of a short list are cheap next
// to the megabytes each mapping holds.
class HugePageCache {
 public:
  // The smallest cached mapping of at least `length` bytes, if it is at most about a quarter
  // larger (kept only for arrays of about its size: trimming a large call's mapping down for
  // a small array would leave the next large call to map and fault it in again), trimmed to
  // exactly `length`; nullptr if none.
  void* Take(size_t length) {
    std::lock_guard<std::mutex> lock(mutex_);
    const size_t largest_fit = length + length / 4 + kHugePageBytes;
    size_t best = mappings_.size();
    for (size_t i = 0; i < mappings_.size(); ++i) {
      const size_t candidate = mappings_[i].length;
      if (candidate >= length && candidate <= largest_fit &&
          (best == mappings_.size() || candidate < mappings_[best].length)) {
        best = i;
      }
    }
    if (best == mappings_.size()) return nullptr;
    const Mapping found = mappings_[best];
    mappings_.erase(mappings_.begin() + static_cast<std::ptrdiff_t>(best));
    cached_bytes_ -= found.length;
    if (found.length > length) {
      munmap(static_cast<char*>(found.start) + length, found.length - length);
    }
    return found.start;
  }

  // Keeps the mapping if it fits under the limit; false: the caller unmaps it.
  bool Put(void* start, size_t length) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (cached_bytes_ + length > limit_) return false;
    mappings_.push_back({start, length});
    cached_bytes_ += length;
    return true;
  }

  void SetLimit(size_t bytes) {
    std::vector<Mapping> evicted;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      limit_ = bytes;
      // Oldest first: the most recently released mappings are the likeliest to be reused.
      while (cached_bytes_ > limit_) {
        evicted.push_back(mappings_.front());
        cached_bytes_ -= mappings_.front().length;
        mappings_.erase(mappings_.begin());
      }
    }
    for (const Mapping& m : evicted) munmap(m.start, m.length);
  }

  size_t Limit() {
    std::lock_guard<std::mutex> lock(mutex_);
    return limit_;
  }
  size_t CachedBytes() {
    std::lock_guard<std::mutex> lock(mutex_);
    return cached_bytes_;
  }

 private:
  std::mutex mutex_;
  std::vector<Mapping> mappings_;  // oldest first
  size_t cached_bytes_ = 0;
  size_t limit_ = kDefaultHugePageCacheBytes;
};

HugePageCache& Cache() {
  static HugePageCache* cache = new HugePageCache;  // never destroyed: used until exit
  return *cache;
}

void* MapFresh(size_t length) {
  // Map a huge page more than needed, keep the 2 MiB-aligned middle, unmap the rest.
  void* mapped = mmap(nullptr, length + kHugePageBytes, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED) throw std::bad_alloc();
  const uintptr_t start = reinterpret_cast<uintptr_t>(mapped);
  const uintptr_t aligned = (start + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  if (aligned > start) munmap(mapped, aligned - start);
  const uintptr_t end = start + length + kHugePageBytes;
  if (end > aligned + length) {
    munmap(reinterpret_cast<void*>(aligned + length), end - aligned - length);
  }
  madvise(reinterpret_cast<void*>(aligned), length, MADV_HUGEPAGE);
  return reinterpret_cast<void*>(aligned);
}

}  // namespace

void* MapHugePages(size_t length) {
  if (void* reused = Cache().Take(length)) return reused;
  return MapFresh(length);
}

void UnmapHugePages(void* mapping, size_t length) {
  if (!Cache().Put(mapping, length)) munmap(mapping, length);
}

void SetHugePageCacheLimit(size_t bytes) { Cache().SetLimit(bytes); }
size_t HugePageCacheLimit() { return Cache().Limit(); }
size_t HugePageCachedBytes() { return Cache().CachedBytes(); }

}  // namespace koma::platform

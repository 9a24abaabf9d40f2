// The huge-page mappings behind HugePageMemory (platform/huge_page_memory.h), with a bounded
// cache of released ones.
//
// A fresh anonymous mapping costs a page fault and a kernel page clear per page on first
// touch. On this project's VMs that first touch ran at ~1.5 GB/s: at 1M frames RetimeFast
// maps ~100 MB of working arrays per call, and perf put a quarter of the call in
// clear_page_erms. A released mapping therefore goes into a small cache instead of back to
// the kernel, and the next large array of about its size (up to a quarter smaller) reuses its
// pages, already resident. The cache holds at most HugePageCacheLimit() bytes (default kDefaultCacheBytes);
// whatever does not fit is unmapped at once, so resident memory is at most the live arrays
// plus that limit.
#ifndef KOMA_PLATFORM_HUGE_PAGE_POOL_H_
#define KOMA_PLATFORM_HUGE_PAGE_POOL_H_

#include <cstddef>

namespace koma::platform {

inline constexpr size_t kHugePageBytes = size_t{2} << 20;  // x86-64's 2 MiB pages

// `bytes` rounded up to whole huge pages: the length to map for an array of that size.
inline constexpr size_t RoundUpToHugePages(size_t bytes) {
  return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
}
inline constexpr size_t kDefaultHugePageCacheBytes = size_t{256} << 20;

// A readable, writable, 2 MiB-aligned mapping of `length` bytes (a multiple of
// kHugePageBytes), marked MADV_HUGEPAGE. Contents are unspecified (a reused mapping keeps
// what its last owner wrote). Throws std::bad_alloc when the system has no memory.
void* MapHugePages(size_t length);
// Releases a mapping from MapHugePages, of the same length: into the cache if it fits under
// the limit, else back to the system.
void UnmapHugePages(void* mapping, size_t length);

// The cache's limit in bytes; 0 turns it off. Lowering it unmaps what no longer fits.
void SetHugePageCacheLimit(size_t bytes);
size_t HugePageCacheLimit();
// Bytes held in the cache now (for tests and metrics).
size_t HugePageCachedBytes();

}  // namespace koma::platform

#endif  // KOMA_PLATFORM_HUGE_PAGE_POOL_H_

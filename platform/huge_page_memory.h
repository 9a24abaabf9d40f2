// Large arrays on transparent huge pages: what koma_server gives core's LargeArray
// (core/large_array.h), its protobuf arenas and its large response slices.
//
// At 1M frames RetimeFast allocates ~90 MB of working arrays per call (runs, distance tables,
// the hold queue). Fresh 4 KiB pages cost a page fault each (~22,000 per call; perf put
// ~15 % of the call in the kernel's fault and page-clearing paths), and the arrays are read
// at random, so they also miss the TLB. Blocks of at least kLargeBlockBytes are mapped
// 2 MiB-aligned and marked MADV_HUGEPAGE: the kernel backs them with 2 MiB pages where it can
// (512x fewer faults and TLB entries). Smaller blocks use operator new as usual. Where
// transparent huge pages are off ("never"), madvise changes nothing and the blocks are plain
// pages. Released mappings go to a bounded cache for the next large block
// (platform/huge_page_pool.h).
#ifndef KOMA_PLATFORM_HUGE_PAGE_MEMORY_H_
#define KOMA_PLATFORM_HUGE_PAGE_MEMORY_H_

#include <cstddef>
#include <memory_resource>

namespace koma::platform {

inline constexpr size_t kLargeBlockBytes = size_t{4} << 20;  // smaller blocks: operator new

// A block of `bytes` (any alignment up to 2 MiB for large blocks, operator new's for small
// ones); FreeBlock takes it back with the same size. Throws std::bad_alloc when out of memory.
void* AllocateBlock(size_t bytes);
void FreeBlock(void* block, size_t bytes);

// The same two as a std::pmr::memory_resource (one for the whole process).
std::pmr::memory_resource* HugePageMemory();

// Makes core's LargeArrays (core/large_array.h) use HugePageMemory(). Programs call it at
// start-up: koma_server, koma_echo_server and the benchmarks.
void UseHugePagesForLargeArrays();

}  // namespace koma::platform

#endif  // KOMA_PLATFORM_HUGE_PAGE_MEMORY_H_

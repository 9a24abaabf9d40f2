// std::vector for RetimeFast's large working arrays, backed by transparent huge pages.
//
// At 1M frames RetimeFast allocates ~90 MB of working arrays per call (runs, distance tables,
// the hold queue). Fresh 4 KiB pages cost a page fault each (~22,000 per call; perf put
// ~15 % of the call in the kernel's fault and page-clearing paths), and the arrays are read
// at random, so they also miss the TLB. Arrays of at least kMinBytes are mapped 2 MiB-aligned
// and marked MADV_HUGEPAGE: the kernel backs them with 2 MiB pages where it can (512x fewer
// faults and TLB entries). Smaller arrays use operator new as usual. Where transparent huge
// pages are off ("never"), madvise changes nothing and the arrays are plain pages. Released
// mappings go to a bounded cache for the next large array (core/huge_page_pool.h).
#ifndef KOMA_CORE_HUGE_PAGE_VECTOR_H_
#define KOMA_CORE_HUGE_PAGE_VECTOR_H_

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/huge_page_pool.h"

namespace koma {

template <typename T>
class HugePageAllocator {
 public:
  using value_type = T;

  static constexpr size_t kHugePage = kHugePageBytes;
  static constexpr size_t kMinBytes = size_t{4} << 20;  // smaller arrays: operator new

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) {}  // NOLINT: rebinding, as std::allocator

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kMinBytes) return static_cast<T*>(::operator new(bytes));
    return static_cast<T*>(MapHugePages(RoundUpToHugePages(bytes)));
  }

  void deallocate(T* p, size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < kMinBytes) {
      ::operator delete(p);
    } else {
      UnmapHugePages(p, RoundUpToHugePages(bytes));
    }
  }

  // Default-initialises: HugePageVector<double>(n) and resize(n) leave the doubles
  // unwritten, as new double[n] does, instead of zeroing them first (every user fills its
  // arrays; zeroing forward kinematics' output was ~1.5 % of a Pitch-size call). Types with
  // default member initialisers still get them; assign(n, 0.0) still writes zeros.
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }

};

template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace koma

#endif  // KOMA_CORE_HUGE_PAGE_VECTOR_H_

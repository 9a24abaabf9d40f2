// std::vector for an algorithm's large working arrays, with the memory chosen by the program.
//
// At 1M frames RetimeFast holds ~90 MB of working arrays per call (runs, distance tables, the
// hold queue) and forward kinematics' output is as large again. Where those bytes come from
// is not an algorithm's business: core asks LargeArrayMemory() and the program decides what
// that is. By default it is operator new (tests, the CLI's reports, the fuzzers); koma_server,
// koma_echo_server and the benchmarks install huge-page mappings with a bounded cache
// (platform/huge_page_memory.h), which save the page faults and TLB misses of large fresh
// arrays. The choice changes no value an algorithm computes.
#ifndef KOMA_CORE_LARGE_ARRAY_H_
#define KOMA_CORE_LARGE_ARRAY_H_

#include <cstddef>
#include <memory_resource>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace koma {

// The memory large arrays are taken from: std::pmr::new_delete_resource() until a program
// sets another. Set it once at start-up, before any call; arrays keep the resource they were
// made with, so changing it later is safe but only affects new arrays.
std::pmr::memory_resource* LargeArrayMemory();
void SetLargeArrayMemory(std::pmr::memory_resource* memory);

template <typename T>
class LargeArrayAllocator {
 public:
  using value_type = T;
  // Moves and swaps take the memory along, so moving an array never copies its elements.
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_swap = std::true_type;

  LargeArrayAllocator() noexcept : memory_(LargeArrayMemory()) {}
  template <typename U>
  LargeArrayAllocator(const LargeArrayAllocator<U>& other) noexcept  // NOLINT: rebinding
      : memory_(other.memory()) {}

  T* allocate(size_t n) {
    if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(memory_->allocate(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, size_t n) noexcept {
    memory_->deallocate(p, n * sizeof(T), alignof(T));
  }

  // Default-initialises: LargeArray<double>(n) and resize(n) leave the doubles unwritten, as
  // new double[n] does, instead of zeroing them first (every user fills its arrays; zeroing
  // forward kinematics' output was ~1.5 % of a Pitch-size call). Types with default member
  // initialisers still get them; assign(n, 0.0) still writes zeros.
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  std::pmr::memory_resource* memory() const noexcept { return memory_; }

  template <typename U>
  bool operator==(const LargeArrayAllocator<U>& other) const noexcept {
    return memory_ == other.memory() || memory_->is_equal(*other.memory());
  }
  template <typename U>
  bool operator!=(const LargeArrayAllocator<U>& other) const noexcept {
    return !(*this == other);
  }

 private:
  std::pmr::memory_resource* memory_;
};

template <typename T>
using LargeArray = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace koma

#endif  // KOMA_CORE_LARGE_ARRAY_H_

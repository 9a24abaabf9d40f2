#include "core/large_array.h"

#include <atomic>

namespace koma {
namespace {

// Read by every array made; set once at start-up (acquire/release so a resource installed
// before threads start is seen whole by them).
std::atomic<std::pmr::memory_resource*>& Memory() {
  static std::atomic<std::pmr::memory_resource*> memory{std::pmr::new_delete_resource()};
  return memory;
}

}  // namespace

std::pmr::memory_resource* LargeArrayMemory() { return Memory().load(std::memory_order_acquire); }

void SetLargeArrayMemory(std::pmr::memory_resource* memory) {
  Memory().store(memory != nullptr ? memory : std::pmr::new_delete_resource(),
                 std::memory_order_release);
}

}  // namespace koma

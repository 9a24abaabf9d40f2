#include "platform/huge_page_memory.h"

#include <new>

#include "core/large_array.h"
#include "platform/huge_page_pool.h"

namespace koma::platform {
namespace {

class HugePageResource final : public std::pmr::memory_resource {
 private:
  // Operator new's alignment covers every type core keeps in a LargeArray; a huge-page
  // mapping is 2 MiB-aligned.
  void* do_allocate(size_t bytes, size_t alignment) override {
    if (bytes < kLargeBlockBytes && alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) {
      return ::operator new(bytes, std::align_val_t{alignment});
    }
    return AllocateBlock(bytes);
  }
  void do_deallocate(void* block, size_t bytes, size_t alignment) override {
    if (bytes < kLargeBlockBytes && alignment > __STDCPP_DEFAULT_NEW_ALIGNMENT__) {
      ::operator delete(block, std::align_val_t{alignment});
      return;
    }
    FreeBlock(block, bytes);
  }
  bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override {
    return this == &other;
  }
};

}  // namespace

void* AllocateBlock(size_t bytes) {
  if (bytes < kLargeBlockBytes) return ::operator new(bytes);
  return MapHugePages(RoundUpToHugePages(bytes));
}

void FreeBlock(void* block, size_t bytes) {
  if (bytes < kLargeBlockBytes) {
    ::operator delete(block);
  } else {
    UnmapHugePages(block, RoundUpToHugePages(bytes));
  }
}

std::pmr::memory_resource* HugePageMemory() {
  static HugePageResource* memory = new HugePageResource;  // never destroyed: used until exit
  return memory;
}

void UseHugePagesForLargeArrays() { SetLargeArrayMemory(HugePageMemory()); }

}  // namespace koma::platform

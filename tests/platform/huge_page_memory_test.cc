#include "platform/huge_page_memory.h"

#include <gtest/gtest.h>

#include <cstdint>

#include "core/large_array.h"
#include "platform/huge_page_pool.h"

namespace koma::platform {
namespace {

// Installs HugePageMemory for core's LargeArrays during a test, as koma_server's main does.
class HugePageMemoryTest : public ::testing::Test {
 protected:
  void SetUp() override { UseHugePagesForLargeArrays(); }
  void TearDown() override { SetLargeArrayMemory(nullptr); }
};

TEST_F(HugePageMemoryTest, LargeArraysAreHugePageAlignedAndKeepTheirContentsWhenGrown) {
  LargeArray<double> values;
  EXPECT_EQ(values.get_allocator().memory(), HugePageMemory());
  for (int k = 0; k < 3'000'000; ++k) values.push_back(0.5 * k);  // grows past 4 MiB several times
  EXPECT_EQ(reinterpret_cast<uintptr_t>(values.data()) % kHugePageBytes, 0u);
  for (int k = 0; k < 3'000'000; k += 9973) ASSERT_EQ(values[k], 0.5 * k);
  values.assign(100, 1.0);
  values.shrink_to_fit();  // back under the threshold: operator new
  EXPECT_EQ(values.size(), 100u);
  EXPECT_EQ(values[99], 1.0);
}

TEST_F(HugePageMemoryTest, SmallAndEmptyArraysWork) {
  LargeArray<int> empty;
  EXPECT_TRUE(empty.empty());
  LargeArray<int> small(10, 7);
  LargeArray<int> copy = small;
  copy.swap(small);
  EXPECT_EQ(small, copy);
  EXPECT_EQ(copy[9], 7);
}

// An array made before the program switched memory is freed to the memory it came from, and
// moves between arrays of either kind keep their elements.
TEST_F(HugePageMemoryTest, ArraysKeepTheMemoryTheyWereMadeWith) {
  SetLargeArrayMemory(nullptr);
  LargeArray<double> plain(size_t{1} << 20, 2.0);  // 8 MiB from operator new
  EXPECT_EQ(plain.get_allocator().memory(), std::pmr::new_delete_resource());
  UseHugePagesForLargeArrays();
  LargeArray<double> huge(size_t{1} << 20, 3.0);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(huge.data()) % kHugePageBytes, 0u);
  huge = std::move(plain);  // takes plain's memory along (no element copy)
  EXPECT_EQ(huge.get_allocator().memory(), std::pmr::new_delete_resource());
  EXPECT_EQ(huge[12345], 2.0);
}

TEST(HugePageBlockTest, LargeBlocksAreWholeHugePagesAndGoBackToTheCache) {
  const size_t saved = HugePageCacheLimit();
  SetHugePageCacheLimit(0);
  SetHugePageCacheLimit(size_t{64} << 20);
  void* small = AllocateBlock(kLargeBlockBytes - 1);
  FreeBlock(small, kLargeBlockBytes - 1);
  EXPECT_EQ(HugePageCachedBytes(), 0u);  // operator new's, not a mapping
  void* large = AllocateBlock(kLargeBlockBytes + 1);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(large) % kHugePageBytes, 0u);
  FreeBlock(large, kLargeBlockBytes + 1);
  EXPECT_EQ(HugePageCachedBytes(), RoundUpToHugePages(kLargeBlockBytes + 1));
  SetHugePageCacheLimit(saved);
}

}  // namespace
}  // namespace koma::platform

#include "platform/huge_page_pool.h"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

namespace koma::platform {
namespace {

constexpr size_t kPage = kHugePageBytes;

// Restores the process-wide limit (and empties the cache) after each test.
class HugePagePoolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    saved_limit_ = HugePageCacheLimit();
    SetHugePageCacheLimit(0);
  }
  void TearDown() override { SetHugePageCacheLimit(saved_limit_); }

 private:
  size_t saved_limit_ = 0;
};

TEST_F(HugePagePoolTest, MappingsAreAlignedWritableAndReusedAfterRelease) {
  SetHugePageCacheLimit(16 * kPage);
  char* first = static_cast<char*>(MapHugePages(4 * kPage));
  EXPECT_EQ(reinterpret_cast<uintptr_t>(first) % kPage, 0u);
  std::memset(first, 0x5a, 4 * kPage);
  UnmapHugePages(first, 4 * kPage);
  EXPECT_EQ(HugePageCachedBytes(), 4 * kPage);
  // The next mapping of that size is the same pages, still holding what was written.
  char* second = static_cast<char*>(MapHugePages(4 * kPage));
  EXPECT_EQ(second, first);
  EXPECT_EQ(second[4 * kPage - 1], 0x5a);
  EXPECT_EQ(HugePageCachedBytes(), 0u);
  UnmapHugePages(second, 4 * kPage);
}

TEST_F(HugePagePoolTest, ASmallerRequestTakesTheSmallestFitTrimmedToItsSize) {
  SetHugePageCacheLimit(64 * kPage);
  void* large = MapHugePages(8 * kPage);
  void* medium = MapHugePages(3 * kPage);
  UnmapHugePages(large, 8 * kPage);
  UnmapHugePages(medium, 3 * kPage);
  void* taken = MapHugePages(2 * kPage);
  EXPECT_EQ(taken, medium);  // 3 pages fit best; its third page went back to the system
  EXPECT_EQ(HugePageCachedBytes(), 8 * kPage);
  // Released with the size it was handed out with, it is cached as 2 pages.
  UnmapHugePages(taken, 2 * kPage);
  EXPECT_EQ(HugePageCachedBytes(), 10 * kPage);
  // 4 pages: the 2-page mapping is too small and the 8-page one far too large (kept for an
  // array of its own size): a fresh mapping, the cache untouched.
  void* fresh_small = MapHugePages(4 * kPage);
  EXPECT_NE(fresh_small, large);
  EXPECT_NE(fresh_small, taken);
  EXPECT_EQ(HugePageCachedBytes(), 10 * kPage);
  munmap(fresh_small, 4 * kPage);  // not through the cache, to keep its count simple
  // Larger than anything cached: a fresh mapping, the cache untouched.
  void* fresh = MapHugePages(9 * kPage);
  EXPECT_NE(fresh, large);
  EXPECT_EQ(HugePageCachedBytes(), 10 * kPage);
  UnmapHugePages(fresh, 9 * kPage);
}

TEST_F(HugePagePoolTest, TheLimitBoundsWhatIsKeptAndLoweringItEvicts) {
  SetHugePageCacheLimit(5 * kPage);
  void* a = MapHugePages(3 * kPage);
  void* b = MapHugePages(3 * kPage);
  UnmapHugePages(a, 3 * kPage);
  UnmapHugePages(b, 3 * kPage);  // 6 pages would exceed 5: unmapped at once
  EXPECT_EQ(HugePageCachedBytes(), 3 * kPage);
  SetHugePageCacheLimit(2 * kPage);
  EXPECT_EQ(HugePageCachedBytes(), 0u);
  // A limit of 0 keeps nothing.
  SetHugePageCacheLimit(0);
  void* c = MapHugePages(kPage);
  UnmapHugePages(c, kPage);
  EXPECT_EQ(HugePageCachedBytes(), 0u);
}

TEST_F(HugePagePoolTest, ThreadsShareTheCacheSafely) {
  SetHugePageCacheLimit(32 * kPage);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([t] {
      for (int round = 0; round < 200; ++round) {
        const size_t pages = 1 + (t + round) % 4;
        auto* p = static_cast<unsigned char*>(MapHugePages(pages * kPage));
        // Each thread writes its own mark over the whole mapping and reads it back: a
        // mapping handed to two threads at once would show the other's mark.
        const unsigned char mark = static_cast<unsigned char>(t + 1);
        std::memset(p, mark, pages * kPage);
        for (size_t k = 0; k < pages * kPage; k += 4096) ASSERT_EQ(p[k], mark);
        UnmapHugePages(p, pages * kPage);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_LE(HugePageCachedBytes(), 32 * kPage);
}

}  // namespace
}  // namespace koma::platform

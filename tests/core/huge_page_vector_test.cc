#include "core/huge_page_vector.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace koma {
namespace {

TEST(HugePageVectorTest, LargeArraysAreHugePageAlignedAndKeepTheirContentsWhenGrown) {
  HugePageVector<double> values;
  for (int k = 0; k < 3'000'000; ++k) values.push_back(0.5 * k);  // grows past 4 MiB several times
  EXPECT_EQ(reinterpret_cast<uintptr_t>(values.data()) % HugePageAllocator<double>::kHugePage, 0u);
  for (int k = 0; k < 3'000'000; k += 9973) ASSERT_EQ(values[k], 0.5 * k);
  values.assign(100, 1.0);
  values.shrink_to_fit();  // back under the threshold: operator new
  EXPECT_EQ(values.size(), 100u);
  EXPECT_EQ(values[99], 1.0);
}

TEST(HugePageVectorTest, SmallAndEmptyArraysWork) {
  HugePageVector<int> empty;
  EXPECT_TRUE(empty.empty());
  HugePageVector<int> small(10, 7);
  HugePageVector<int> copy = small;
  copy.swap(small);
  EXPECT_EQ(small, copy);
  EXPECT_EQ(copy[9], 7);
}

}  // namespace
}  // namespace koma

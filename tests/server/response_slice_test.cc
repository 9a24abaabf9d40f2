#include "server/response_slice.h"

#include <gtest/gtest.h>

#include <cstring>

#include "platform/huge_page_pool.h"

namespace koma::server {
namespace {

using platform::HugePageCachedBytes;
using platform::HugePageCacheLimit;
using platform::kHugePageBytes;
using platform::SetHugePageCacheLimit;

class ResponseSliceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    saved_limit_ = HugePageCacheLimit();
    SetHugePageCacheLimit(0);  // empties the cache
    SetHugePageCacheLimit(size_t{64} << 20);
  }
  void TearDown() override { SetHugePageCacheLimit(saved_limit_); }

 private:
  size_t saved_limit_ = 0;
};

TEST_F(ResponseSliceTest, SmallSliceIsAnOrdinaryOne) {
  {
    grpc::Slice slice = UninitialisedSlice(1000);
    ASSERT_EQ(slice.size(), 1000u);
    std::memset(const_cast<uint8_t*>(slice.begin()), 7, slice.size());
  }
  EXPECT_EQ(HugePageCachedBytes(), 0u);
}

// A large slice is a huge-page mapping of whole 2 MiB pages; when gRPC drops its last
// reference the mapping goes back to the cache, and the next slice of that size reuses it.
TEST_F(ResponseSliceTest, LargeSliceReturnsItsMappingForTheNextOne) {
  constexpr size_t kBytes = (size_t{5} << 20) + 123;  // rounds up to 6 MiB
  const uint8_t* first = nullptr;
  {
    grpc::Slice slice = UninitialisedSlice(kBytes);
    ASSERT_EQ(slice.size(), kBytes);
    first = slice.begin();
    EXPECT_EQ(reinterpret_cast<uintptr_t>(first) % kHugePageBytes, 0u);
    std::memset(const_cast<uint8_t*>(slice.begin()), 1, slice.size());  // all of it writable
    grpc::Slice copy = slice;  // a second reference: the mapping stays until both are gone
    EXPECT_EQ(HugePageCachedBytes(), 0u);
  }
  EXPECT_EQ(HugePageCachedBytes(), size_t{6} << 20);
  grpc::Slice again = UninitialisedSlice(kBytes);
  EXPECT_EQ(again.begin(), first);
  EXPECT_EQ(HugePageCachedBytes(), 0u);
}

}  // namespace
}  // namespace koma::server

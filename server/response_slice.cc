#include "server/response_slice.h"

#include <grpc/slice.h>

#include "core/huge_page_pool.h"
#include "core/huge_page_vector.h"

namespace koma::server {
namespace {

// gRPC's destroy callback: any thread, once the last reference to the slice is gone.
void ReturnMapping(void* start, size_t bytes) { UnmapHugePages(start, RoundUpToHugePages(bytes)); }

}  // namespace

grpc::Slice UninitialisedSlice(size_t bytes) {
  if (bytes < HugePageAllocator<char>::kMinBytes) return grpc::Slice(bytes);
  void* start = MapHugePages(RoundUpToHugePages(bytes));
  return grpc::Slice(grpc_slice_new_with_len(start, bytes, ReturnMapping),
                     grpc::Slice::STEAL_REF);
}

}  // namespace koma::server

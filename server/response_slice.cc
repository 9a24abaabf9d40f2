#include "server/response_slice.h"

#include <grpc/slice.h>

#include "platform/huge_page_memory.h"

namespace koma::server {
namespace {

// gRPC's destroy callback: any thread, once the last reference to the slice is gone.
void ReturnBlock(void* start, size_t bytes) { platform::FreeBlock(start, bytes); }

}  // namespace

grpc::Slice UninitialisedSlice(size_t bytes) {
  if (bytes < platform::kLargeBlockBytes) return grpc::Slice(bytes);
  void* start = platform::AllocateBlock(bytes);
  return grpc::Slice(grpc_slice_new_with_len(start, bytes, ReturnBlock),
                     grpc::Slice::STEAL_REF);
}

}  // namespace koma::server

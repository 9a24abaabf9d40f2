// The buffer a hand-encoded response is written into before gRPC sends it.
#ifndef KOMA_SERVER_RESPONSE_SLICE_H_
#define KOMA_SERVER_RESPONSE_SLICE_H_

#include <grpcpp/support/slice.h>

#include <cstddef>

namespace koma::server {

// `bytes` uninitialised bytes, ours alone until they are handed to gRPC. Large ones (4 MiB and
// up) are huge-page blocks from platform/huge_page_memory.h, given back to its cache
// when gRPC has sent them: with the cache on, a large call's response reuses memory a call
// before it released (forward kinematics' positions of the same call, sized for it: see
// server/skeletal_handler.cc) instead of faulting in and zeroing fresh pages, ~10 ms per
// 74 MB here.
grpc::Slice UninitialisedSlice(size_t bytes);

}  // namespace koma::server

#endif  // KOMA_SERVER_RESPONSE_SLICE_H_

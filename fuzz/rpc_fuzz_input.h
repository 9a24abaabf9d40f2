// The request bytes an RPC fuzz target hands to its handler, and the small limits it runs with.
//
// The first input byte chooses how the rest is cut into slices (gRPC hands a large message
// over in many), so the server's own parsers that read across slices
// (server/skeletal_parse.h) see every split; the other bytes are the serialised request.
#ifndef KOMA_FUZZ_RPC_FUZZ_INPUT_H_
#define KOMA_FUZZ_RPC_FUZZ_INPUT_H_

#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/slice.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "server/request_limits.h"

namespace koma::fuzz {

// Small enough that one input runs in milliseconds under ASan (a 1,000-frame, 64-value clip),
// large enough for every sample request of the seed corpus.
inline server::RequestLimits SmallLimits() {
  server::RequestLimits limits;
  limits.max_values = 200'000;
  limits.max_joints = 256;
  limits.max_audio_samples = 4'000'000;
  limits.max_gltf_animations = 256;
  limits.threads_per_call = 1;
  return limits;
}

struct RpcFuzzInput {
  size_t slice_bytes;  // 1 .. 256, or the whole message in one slice
  std::string_view message;
};

inline RpcFuzzInput SplitFuzzInput(const uint8_t* data, size_t size) {
  if (size == 0) return {1, std::string_view()};
  const size_t selector = data[0];
  const std::string_view message(reinterpret_cast<const char*>(data + 1), size - 1);
  // Half the selectors: one slice; the rest: slices of 1 .. 128 bytes.
  const size_t slice_bytes = selector < 128 ? std::max<size_t>(message.size(), 1) : selector - 127;
  return {slice_bytes, message};
}

inline grpc::ByteBuffer Sliced(const RpcFuzzInput& input) {
  std::vector<grpc::Slice> slices;
  for (size_t at = 0; at < input.message.size(); at += input.slice_bytes) {
    const size_t n = std::min(input.slice_bytes, input.message.size() - at);
    slices.emplace_back(input.message.data() + at, n);
  }
  return grpc::ByteBuffer(slices.data(), slices.size());
}

}  // namespace koma::fuzz

#endif  // KOMA_FUZZ_RPC_FUZZ_INPUT_H_

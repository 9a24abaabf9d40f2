// What a RetimeSkeletal call costs the server on top of gRPC: koma's handler (parse the received
// bytes, validate, FK, RetimeFast, encode the response bytes) against the echo baseline's
// (parse, build a response of the same shape, serialise it), on koma_load's synthetic requests.
// The difference is the CPU that decides koma/echo throughput on the 2 cores once both servers
// pay the same transport; measured here without the network's noise. Single-threaded.
// BM_KomaSkeletalHandlerNoCuts is the same call with cuts off (cut_neighbour_ratio 0): the
// cost of the default cut search (one more SSD pass over the source frames, issue 28).
// BM_KomaSkeletalHandlerPaper names max_hold 3: the paper's algorithm, the work older servers
// did for the request with no options (the anime defaults' rates hold more, issue 41).
#include <benchmark/benchmark.h>

#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/slice.h>

#include <string>

#include "bench/echo_shapes.h"
#include "bench/load/load_request.h"
#include "google/protobuf/arena.h"
#include "server/request_limits.h"
#include "server/skeletal_parse.h"
#include "server/skeletal_request.h"

namespace koma {
namespace {

// The request as gRPC hands it to the server: its serialised bytes in a ByteBuffer.
grpc::ByteBuffer BytesOf(const v1::RetimeSkeletalRequest& request) {
  const std::string bytes = request.SerializeAsString();
  grpc::Slice slice(bytes.data(), bytes.size());
  return grpc::ByteBuffer(&slice, 1);
}

v1::RetimeSkeletalRequest Synthetic(const benchmark::State& state) {
  return load::SyntheticSkeletal(static_cast<int>(state.range(0)), /*joints=*/31, state.range(1),
                                 /*seed=*/1);
}

// koma's handler on `bytes`, as the service runs it.
void RunKomaHandler(benchmark::State& state, const grpc::ByteBuffer& bytes) {
  server::RequestLimits limits;
  limits.threads_per_call = 1;
  for (auto _ : state) {
    google::protobuf::Arena arena;
    auto* request = google::protobuf::Arena::CreateMessage<v1::RetimeSkeletalRequest>(&arena);
    if (!server::ParseSkeletalRequest(bytes, request).ok()) state.SkipWithError("parse");
    server::SkeletalAnswer answer;
    if (!server::RetimeSkeletalAnswer(*request, limits, &answer).ok()) state.SkipWithError("call");
    benchmark::DoNotOptimize(answer.bytes.begin());
  }
}

// The synthetic request with no options: the server's anime defaults.
void BM_KomaSkeletalHandler(benchmark::State& state) {
  RunKomaHandler(state, BytesOf(Synthetic(state)));
}

// The same request with cuts off: the handler skips the cut search.
void BM_KomaSkeletalHandlerNoCuts(benchmark::State& state) {
  v1::RetimeSkeletalRequest request = Synthetic(state);
  request.set_cut_neighbour_ratio(0);
  RunKomaHandler(state, BytesOf(request));
}

// The paper's algorithm (max_hold 3 named: 4 omissions, N / 3 holds): the work a server from
// before the anime defaults did for the request with no options.
void BM_KomaSkeletalHandlerPaper(benchmark::State& state) {
  v1::RetimeSkeletalRequest request = Synthetic(state);
  request.set_max_hold(3);
  RunKomaHandler(state, BytesOf(request));
}

void BM_EchoSkeletalHandler(benchmark::State& state) {
  const grpc::ByteBuffer bytes = BytesOf(Synthetic(state));
  for (auto _ : state) {
    google::protobuf::Arena arena;
    auto* request = google::protobuf::Arena::CreateMessage<v1::RetimeSkeletalRequest>(&arena);
    if (!server::ParseSkeletalRequest(bytes, request).ok()) state.SkipWithError("parse");
    auto* response = google::protobuf::Arena::CreateMessage<v1::RetimeSkeletalResponse>(&arena);
    echo::SkeletalLookalike(*request, response);
    grpc::Slice out(response->ByteSizeLong());  // what gRPC's serialiser writes into
    response->SerializeWithCachedSizesToArray(const_cast<uint8_t*>(out.begin()));
    benchmark::DoNotOptimize(out.begin());
  }
}

// Args: frames, positions (1) or BVH channels (0).
BENCHMARK(BM_KomaSkeletalHandler)->Args({129, 0})->Args({129, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EchoSkeletalHandler)->Args({129, 0})->Args({129, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_KomaSkeletalHandler)->Args({100000, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KomaSkeletalHandlerNoCuts)->Args({129, 0})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_KomaSkeletalHandlerPaper)->Args({129, 0})->Args({129, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_KomaSkeletalHandlerNoCuts)->Args({100000, 0})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EchoSkeletalHandler)->Args({100000, 0})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace koma

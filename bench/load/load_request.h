// The one request koma_load sends over and over: read from a file or synthesised
// deterministically, then serialised once so every call shares the same bytes.
#ifndef KOMA_BENCH_LOAD_LOAD_REQUEST_H_
#define KOMA_BENCH_LOAD_LOAD_REQUEST_H_

#include <string>

#include "absl/status/statusor.h"
#include "bench/load/load_options.h"
#include "koma/v1/retime.pb.h"

namespace koma::load {

struct LoadRequest {
  std::string method;       // full gRPC method, "/koma.v1.Retime/RetimeSkeletal"
  std::string bytes;        // the serialised request message
  std::string description;  // "129 frames x 31 joints (channels)" for the report
};

// From options.input when set, else synthesised from --frames/--joints/--curves/--seed.
// Errors name the file (NOT_FOUND, INVALID_ARGUMENT with the parser's line).
absl::StatusOr<LoadRequest> BuildLoadRequest(const LoadOptions& options);

// Synthetic requests, exposed for reuse. Same arguments,
// same bytes.
v1::RetimeSkeletalRequest SyntheticSkeletal(int frames, int joints, bool positions, uint64_t seed);
v1::RetimeCurvesRequest SyntheticCurves(int curves, int frames, uint64_t seed);
v1::LipBlinkRequest SyntheticLipBlink(int curves, int frames, uint64_t seed);

}  // namespace koma::load

#endif  // KOMA_BENCH_LOAD_LOAD_REQUEST_H_

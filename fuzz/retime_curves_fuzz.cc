// Fuzz target: any bytes as a RetimeCurves request, through the server's path: parse,
// validation into the answer (PrepareCurvesAnswer), koma-uchi retiming with small limits
// (CompleteCurvesAnswer) and the wire encoder, whole and in slices (server/curves_response.h).
//
// Every input must be answered OK or with an error status. On OK the encoder's bytes, whole
// and sliced, must equal protobuf's serialisation of HandleRetimeCurves' message.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz/fuzz_check.h"
#include "fuzz/rpc_fuzz_input.h"
#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "server/curves_response.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const koma::fuzz::RpcFuzzInput input = koma::fuzz::SplitFuzzInput(data, size);
  const koma::server::RequestLimits limits = koma::fuzz::SmallLimits();

  koma::v1::RetimeCurvesRequest request;
  if (!request.ParseFromArray(input.message.data(), static_cast<int>(input.message.size()))) {
    return 0;
  }
  koma::server::CurvesAnswer answer;
  absl::Status status = koma::server::PrepareCurvesAnswer(request, limits, &answer);
  if (status.ok()) status = koma::server::CompleteCurvesAnswer(&answer);
  koma::v1::RetimeCurvesResponse reference;
  const absl::Status handled = koma::server::HandleRetimeCurves(request, limits, &reference);
  KOMA_FUZZ_CHECK(status.code() == handled.code(), "the two paths agree on the outcome");
  if (!status.ok()) {
    KOMA_FUZZ_CHECK(!status.message().empty(), "an error must say what is wrong");
    return 0;
  }
  const std::string expected = reference.SerializeAsString();

  const koma::server::CurvesResponseEncoder encoder(answer.set, answer.result);
  if (!answer.file_field.empty()) {
    // A file request: the service writes the retimed file's field (motion3_json, csv_text or
    // spine_json) among the encoder's; the answer must parse to protobuf's response (a Spine
    // file's field 45 is written before fields 20-21, so the order may differ from protobuf's).
    const std::vector<grpc::Slice> slices = koma::server::EncodeInSlices(
        encoder, answer.result, input.slice_bytes, answer.file_field);
    std::string joined;
    for (const grpc::Slice& slice : slices) {
      joined.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
    }
    koma::v1::RetimeCurvesResponse parsed;
    KOMA_FUZZ_CHECK(parsed.ParseFromString(joined), "a file request's answer parses");
    KOMA_FUZZ_CHECK(parsed.SerializeAsString() == expected,
                    "a file request's answer is protobuf's response");
    return 0;
  }
  KOMA_FUZZ_CHECK(encoder.size() == expected.size(), "the encoder's size is protobuf's");
  std::string whole(encoder.size(), '\0');
  encoder.WriteTo(reinterpret_cast<uint8_t*>(whole.data()));
  KOMA_FUZZ_CHECK(whole == expected, "the wire encoder writes protobuf's bytes");

  // In slices of about input.slice_bytes, as the service sends a large answer.
  const std::vector<grpc::Slice> slices =
      koma::server::EncodeInSlices(encoder, answer.result, input.slice_bytes);
  std::string joined;
  for (const grpc::Slice& slice : slices) {
    joined.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  }
  KOMA_FUZZ_CHECK(joined == expected, "the sliced answer is the same bytes");
  return 0;
}

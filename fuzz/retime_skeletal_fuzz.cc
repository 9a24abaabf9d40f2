// Fuzz target: any bytes as a RetimeSkeletal request, through the server's own path: the
// sliced parse that reserves the value array from its length prefix (server/skeletal_parse.h),
// validation, forward kinematics and retiming with small limits, and the wire encoder
// (server/skeletal_response.h).
//
// Every input must be answered OK or with an error status naming the problem. On OK the
// encoder's bytes must equal protobuf's serialisation of HandleRetimeSkeletal's message (the
// typed reference), and the same call again must give the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "fuzz/rpc_fuzz_input.h"
#include "koma/v1/retime.pb.h"
#include "server/skeletal_parse.h"
#include "server/skeletal_request.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const koma::fuzz::RpcFuzzInput input = koma::fuzz::SplitFuzzInput(data, size);
  const koma::server::RequestLimits limits = koma::fuzz::SmallLimits();

  const grpc::ByteBuffer bytes = koma::fuzz::Sliced(input);
  koma::v1::RetimeSkeletalRequest request;
  const absl::Status parsed = koma::server::ParseSkeletalRequest(bytes, &request);
  koma::v1::RetimeSkeletalRequest reference_request;
  const bool reference_parsed = reference_request.ParseFromArray(
      input.message.data(), static_cast<int>(input.message.size()));
  KOMA_FUZZ_CHECK(parsed.ok() == reference_parsed, "the sliced parse agrees with protobuf's");
  if (!parsed.ok()) return 0;
  KOMA_FUZZ_CHECK(request.SerializeAsString() == reference_request.SerializeAsString(),
                  "the sliced parse reads the same message");

  koma::server::SkeletalAnswer answer;
  const absl::Status answered = koma::server::RetimeSkeletalAnswer(request, limits, &answer);
  koma::v1::RetimeSkeletalResponse reference;
  const absl::Status handled = koma::server::HandleRetimeSkeletal(request, limits, &reference);
  KOMA_FUZZ_CHECK(answered.code() == handled.code(), "the two paths agree on the outcome");
  if (!answered.ok()) {
    KOMA_FUZZ_CHECK(!answered.message().empty(), "an error must say what is wrong");
    return 0;
  }
  const std::string encoded(reinterpret_cast<const char*>(answer.bytes.begin()),
                            answer.bytes.size());
  KOMA_FUZZ_CHECK(encoded == reference.SerializeAsString(),
                  "the wire encoder writes protobuf's bytes");

  koma::server::SkeletalAnswer again;
  KOMA_FUZZ_CHECK(koma::server::RetimeSkeletalAnswer(request, limits, &again).ok(), "again OK");
  KOMA_FUZZ_CHECK(again.bytes.size() == answer.bytes.size() &&
                      std::string(reinterpret_cast<const char*>(again.bytes.begin()),
                                  again.bytes.size()) == encoded,
                  "same request, same bytes");
  return 0;
}

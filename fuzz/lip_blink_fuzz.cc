// Fuzz target: any bytes as a LipBlink request, through the server's handler with small
// limits: parse, validation, mouth and eye conversion (seeded auto-blink included), and the
// response's serialisation.
//
// Every input must be answered OK or with an error status. On OK the response must serialise
// and parse back (a Spine skeleton's answer carry the skeleton, which must parse again), and the same request must give the same bytes a second time (the seed makes
// auto-blink reproducible).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "formats/spine.h"
#include "fuzz/rpc_fuzz_input.h"
#include "koma/v1/retime.pb.h"
#include "server/lip_blink_request.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const koma::fuzz::RpcFuzzInput input = koma::fuzz::SplitFuzzInput(data, size);
  const koma::server::RequestLimits limits = koma::fuzz::SmallLimits();

  koma::v1::LipBlinkRequest request;
  if (!request.ParseFromArray(input.message.data(), static_cast<int>(input.message.size()))) {
    return 0;
  }
  koma::v1::LipBlinkResponse response;
  const absl::Status status = koma::server::HandleLipBlink(request, limits, &response);
  if (!status.ok()) {
    KOMA_FUZZ_CHECK(!status.message().empty(), "an error must say what is wrong");
    return 0;
  }
  std::string bytes;
  KOMA_FUZZ_CHECK(response.SerializeToString(&bytes), "the response serialises");
  koma::v1::LipBlinkResponse reread;
  KOMA_FUZZ_CHECK(reread.ParseFromString(bytes), "and parses back");
  // A skeleton's answer is the skeleton, written back so that it reads again.
  if (request.input_case() == koma::v1::LipBlinkRequest::kSpineJson) {
    KOMA_FUZZ_CHECK(response.output_case() == koma::v1::LipBlinkResponse::kSpineJson,
                    "a skeleton's answer carries spine_json");
    KOMA_FUZZ_CHECK(koma::formats::ParseSpine(response.spine_json()).ok(),
                    "the written skeleton parses");
  }

  koma::v1::LipBlinkResponse again;
  KOMA_FUZZ_CHECK(koma::server::HandleLipBlink(request, limits, &again).ok(), "again OK");
  KOMA_FUZZ_CHECK(again.SerializeAsString() == bytes, "same request, same bytes");
  return 0;
}

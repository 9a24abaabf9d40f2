// The two ways to the bytes of a RetimeCurvesResponse that the encoder tests compare
// (curves_response_test.cc, curves_grid_response_test.cc): the wire encoder's own
// (server/curves_response.h) and protobuf's, from the messages it replaces.
#ifndef KOMA_TESTS_SERVER_CURVES_RESPONSE_BYTES_H_
#define KOMA_TESTS_SERVER_CURVES_RESPONSE_BYTES_H_

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "koma/v1/retime.pb.h"
#include "server/curves_request.h"
#include "server/curves_response.h"

namespace koma::testing {

// The encoder's bytes, written into a buffer with guard bytes after size() to catch a write
// past the end.
inline std::string Encoded(const CurveSet& set, const KomaUchiResult& result) {
  const server::CurvesResponseEncoder encoder(set, result);
  constexpr size_t kGuard = 64;
  std::string buffer(encoder.size() + kGuard, '\x5a');
  encoder.WriteTo(reinterpret_cast<uint8_t*>(buffer.data()));
  EXPECT_EQ(buffer.substr(encoder.size()), std::string(kGuard, '\x5a')) << "wrote past size()";
  buffer.resize(encoder.size());
  return buffer;
}

// The reference: the response as messages, serialised by protobuf.
inline std::string Serialised(const CurveSet& set, const KomaUchiResult& result) {
  v1::RetimeCurvesResponse response;
  server::FillCurvesResponse(set, result, &response);
  std::string bytes;
  EXPECT_TRUE(response.SerializeToString(&bytes));
  return bytes;
}

}  // namespace koma::testing

#endif  // KOMA_TESTS_SERVER_CURVES_RESPONSE_BYTES_H_

// Pieces of the protobuf wire format shared by the hand-written response encoders
// (server/curves_response.cc, server/skeletal_response.cc): tags, lengths and the proto3 rule
// for doubles, so both write exactly what protobuf's serialiser would.
#ifndef KOMA_SERVER_WIRE_BYTES_H_
#define KOMA_SERVER_WIRE_BYTES_H_

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace koma::server::wire {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedOutputStream;

constexpr WireFormatLite::WireType kVarint = WireFormatLite::WIRETYPE_VARINT;
constexpr WireFormatLite::WireType kFixed64 = WireFormatLite::WIRETYPE_FIXED64;
constexpr WireFormatLite::WireType kLength = WireFormatLite::WIRETYPE_LENGTH_DELIMITED;

// A field's tag byte (fields 1-15 fit one byte).
constexpr uint8_t Tag(int field, WireFormatLite::WireType type) {
  return static_cast<uint8_t>(field << 3 | type);
}

inline uint64_t Bits(double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// proto3 leaves a singular double out when its bits are all zero (+0.0; -0.0 is written).
inline bool DoubleIsWritten(double value) { return Bits(value) != 0; }

// A length-delimited field of `body` bytes: tag, length, body.
inline size_t LengthField(size_t body) { return 1 + CodedOutputStream::VarintSize64(body) + body; }

// Writes a length-delimited field's tag and length; the body follows.
inline uint8_t* WriteLength(uint8_t tag, size_t length, uint8_t* out) {
  *out++ = tag;
  return CodedOutputStream::WriteVarint64ToArray(length, out);
}

}  // namespace koma::server::wire

#endif  // KOMA_SERVER_WIRE_BYTES_H_

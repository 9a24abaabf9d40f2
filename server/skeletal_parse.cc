#include "server/skeletal_parse.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>
#include <grpcpp/support/proto_buffer_reader.h>

#include <limits>

namespace koma::server {
namespace {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedInputStream;

// Field numbers on the path request.motion.{channels,positions}.values (proto/koma/v1).
constexpr int kRequestMotion = v1::RetimeSkeletalRequest::kMotionFieldNumber;
constexpr int kMotionChannels = v1::SkeletalMotion::kChannelsFieldNumber;
constexpr int kMotionPositions = v1::SkeletalMotion::kPositionsFieldNumber;
constexpr int kValues = v1::JointPositions::kValuesFieldNumber;
static_assert(kValues == v1::ChannelValues::kValuesFieldNumber);

bool IsLengthDelimited(uint32_t tag) {
  return WireFormatLite::GetTagWireType(tag) == WireFormatLite::WIRETYPE_LENGTH_DELIMITED;
}

// Inside a length-delimited message of `length` bytes, calls on_field(field, length) for each
// length-delimited field `wanted(field)` (positioned at its data; it must consume exactly
// `length` bytes or return false) and skips every other field. False on malformed bytes.
template <typename Wanted, typename OnField>
bool ForEachNestedField(CodedInputStream& in, Wanted wanted, OnField on_field) {
  for (;;) {
    const uint32_t tag = in.ReadTag();
    if (tag == 0) return true;  // the end of the (limited) message
    const int field = WireFormatLite::GetTagFieldNumber(tag);
    if (IsLengthDelimited(tag) && wanted(field)) {
      uint32_t length = 0;
      if (!in.ReadVarint32(&length)) return false;
      if (!on_field(field, length)) return false;
    } else if (!WireFormatLite::SkipField(&in, tag)) {
      return false;
    }
  }
}

}  // namespace

PackedValueCounts ScanPackedValueCounts(const grpc::ByteBuffer& bytes) {
  PackedValueCounts counts;
  // ProtoBufferReader only reads the slices; it takes a non-const pointer for its API.
  grpc::ProtoBufferReader reader(const_cast<grpc::ByteBuffer*>(&bytes));
  CodedInputStream in(&reader);
  in.SetTotalBytesLimit(std::numeric_limits<int>::max());
  const auto descend = [&in](uint32_t length, auto inner) {
    const CodedInputStream::Limit limit = in.PushLimit(static_cast<int>(length));
    const bool ok = inner() && in.ConsumedEntireMessage() && in.BytesUntilLimit() == 0;
    in.PopLimit(limit);
    return ok;
  };
  const bool ok = ForEachNestedField(
      in, [](int field) { return field == kRequestMotion; },
      [&](int, uint32_t motion_length) {
        return descend(motion_length, [&] {
          return ForEachNestedField(
              in, [](int field) { return field == kMotionChannels || field == kMotionPositions; },
              [&](int form, uint32_t form_length) {
                return descend(form_length, [&] {
                  return ForEachNestedField(
                      in, [](int field) { return field == kValues; },
                      [&](int, uint32_t values_length) {
                        // A later occurrence replaces (oneof) or extends (repeated) an
                        // earlier one; the counts only size a reservation, so add up.
                        const int64_t doubles = values_length / sizeof(double);
                        (form == kMotionPositions ? counts.positions : counts.channels) += doubles;
                        return in.Skip(static_cast<int>(values_length));
                      });
                });
              });
        });
      });
  return ok ? counts : PackedValueCounts{};
}

absl::Status ParseSkeletalRequest(const grpc::ByteBuffer& bytes,
                                  v1::RetimeSkeletalRequest* request) {
  const PackedValueCounts counts = ScanPackedValueCounts(bytes);
  // Reserving creates the oneof member the bytes hold anyway; a message that holds both (a
  // later one wins) simply loses the first reservation. Capacity is not contents: the parsed
  // message is the same as without it.
  if (counts.positions > 0 && counts.positions <= std::numeric_limits<int>::max()) {
    request->mutable_motion()->mutable_positions()->mutable_values()->Reserve(
        static_cast<int>(counts.positions));
  } else if (counts.channels > 0 && counts.channels <= std::numeric_limits<int>::max()) {
    request->mutable_motion()->mutable_channels()->mutable_values()->Reserve(
        static_cast<int>(counts.channels));
  }
  grpc::ProtoBufferReader reader(const_cast<grpc::ByteBuffer*>(&bytes));
  CodedInputStream in(&reader);
  in.SetTotalBytesLimit(std::numeric_limits<int>::max());
  if (!request->MergeFromCodedStream(&in) || !in.ConsumedEntireMessage()) {
    return absl::InvalidArgumentError(
        "request: the bytes are not a valid koma.v1.RetimeSkeletalRequest (protobuf parse "
        "failed)");
  }
  return absl::OkStatus();
}

}  // namespace koma::server

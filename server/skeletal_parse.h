// Parsing a RetimeSkeletalRequest from the bytes gRPC received, with its big packed array
// allocated once at its final size.
//
// protobuf's parser grows a packed repeated field as the bytes arrive, slice by slice, doubling
// its capacity: for a 100,000-frame clip (71 MB of positions) it ends at 102 MB of capacity
// and briefly holds the 51 MB and the 102 MB copies at once, on top of the 71 MB of received
// bytes (measured with valgrind's massif: 238 MB at the peak of one call). Reading the field's
// length first (the wire format says it before the data) and reserving exactly that much makes
// the parse copy each value once into memory it keeps.
#ifndef KOMA_SERVER_SKELETAL_PARSE_H_
#define KOMA_SERVER_SKELETAL_PARSE_H_

#include <grpcpp/support/byte_buffer.h>

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"

namespace koma::server {

// The number of doubles in motion.positions.values (or motion.channels.values) of the
// serialised request, read from the length prefixes without parsing the values; 0 when the
// field is absent or the bytes are not well formed (the parse then reports them).
struct PackedValueCounts {
  int64_t positions = 0;
  int64_t channels = 0;
};
PackedValueCounts ScanPackedValueCounts(const grpc::ByteBuffer& bytes);

// Parses `bytes` into `request` (which must be empty), reserving the motion's value array at
// its final size first. INVALID_ARGUMENT when the bytes are not a RetimeSkeletalRequest.
absl::Status ParseSkeletalRequest(const grpc::ByteBuffer& bytes,
                                  v1::RetimeSkeletalRequest* request);

}  // namespace koma::server

#endif  // KOMA_SERVER_SKELETAL_PARSE_H_

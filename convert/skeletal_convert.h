// SkeletalClip (formats/ side) <-> koma.v1 messages (wire side), for the CLI and for the
// server's file-carrying requests.
#ifndef KOMA_CONVERT_SKELETAL_CONVERT_H_
#define KOMA_CONVERT_SKELETAL_CONVERT_H_

#include "absl/status/statusor.h"
#include "core/retime.h"
#include "core/skeleton.h"
#include "koma/v1/retime.pb.h"

namespace koma::convert {

// Channel form, every field copied.
v1::SkeletalMotion ToProto(const SkeletalClip& clip);

// The retimed clip of a response, on the skeleton that was sent. INVALID_ARGUMENT if the
// server's motion does not fit that skeleton (a server bug, reported, never written).
absl::StatusOr<SkeletalClip> ClipFromResponse(const v1::RetimeSkeletalResponse& response,
                                              const Skeleton& skeleton);

// The response's timing map as the core type (for the timing sheet writer).
TimingMap TimingMapFromResponse(const v1::RetimeSkeletalResponse& response);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_SKELETAL_CONVERT_H_

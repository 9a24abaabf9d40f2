// RetimeSkeletal with a glTF file (RetimeSkeletalRequest.gltf; docs/formats.md, "glTF 2.0 and
// VRM"): each picked animation is sampled at its source rate, its joints' world positions
// retimed through the ordinary positions-form path, and the file written back with the
// retimed keys (docs/semantics.md, "glTF animations").
#ifndef KOMA_SERVER_GLTF_REQUEST_H_
#define KOMA_SERVER_GLTF_REQUEST_H_

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"
#include "server/skeletal_request.h"

namespace koma::server {

// The answer as a message: the first retimed animation's timing in the top-level fields, every
// retimed animation in gltf_animations, the file in `gltf` (unless return_motion is false).
// `described` gets the first animation's frame and joint counts (log line, metrics).
absl::Status HandleRetimeSkeletalGltf(const v1::RetimeSkeletalRequest& request,
                                      const RequestLimits& limits,
                                      v1::RetimeSkeletalResponse* response,
                                      SkeletalAnswer* described = nullptr);

}  // namespace koma::server

#endif  // KOMA_SERVER_GLTF_REQUEST_H_

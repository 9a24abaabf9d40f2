// RetimeSkeletal with an FBX file (RetimeSkeletalRequest.fbx; docs/formats.md, "FBX"): the
// take is evaluated at the file's frame rate through FBX's transform chain, its models' world
// positions retimed through the ordinary positions-form path, and the file written back with
// the take's curves keyed on every output frame (formats/fbx_scene.h, WriteFbxRetimed).
#ifndef KOMA_SERVER_FBX_REQUEST_H_
#define KOMA_SERVER_FBX_REQUEST_H_

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"
#include "server/skeletal_request.h"

namespace koma::server {

// The take's timing in the top-level fields and fbx_take, the file in `fbx` (unless
// return_motion is false). `described` gets the frame and joint counts (log line, metrics).
absl::Status HandleRetimeSkeletalFbx(const v1::RetimeSkeletalRequest& request,
                                     const RequestLimits& limits,
                                     v1::RetimeSkeletalResponse* response,
                                     SkeletalAnswer* described = nullptr);

}  // namespace koma::server

#endif  // KOMA_SERVER_FBX_REQUEST_H_

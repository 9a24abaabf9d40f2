// LipBlink with spine_json (convert/spine_lip_blink.h): the skeleton parsed, its slots
// checked, the decoded request answered by HandleLipBlink (voice or not), and the slots'
// attachment timelines written back into the skeleton (LipBlinkResponse.spine_json). The
// response keeps the decoded request's answer (mouths, eyes, curves at skeleton.fps, voice).
//
// Errors: INVALID_ARGUMENT naming the field and the value (`spine.mouth_slot: no slot named
// "nose" (the skeleton has ...)`, "spine_json: slots[2].name: ..."); RESOURCE_EXHAUSTED over
// --max_file_bytes or the memory budget, as for the other files.
#ifndef KOMA_SERVER_LIP_BLINK_SPINE_H_
#define KOMA_SERVER_LIP_BLINK_SPINE_H_

#include "absl/status/status.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

struct LipBlinkMotionShape;  // server/lip_blink_request.h

absl::Status HandleLipBlinkSpine(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                 v1::LipBlinkResponse* response, LipBlinkMotionShape* shape);

}  // namespace koma::server

#endif  // KOMA_SERVER_LIP_BLINK_SPINE_H_

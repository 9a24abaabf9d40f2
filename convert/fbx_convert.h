// An FBX take as the positions-form SkeletalMotion RetimeSkeletal measures (shared by the
// server's FBX requests and the CLI's --report, so both see the same figures).
#ifndef KOMA_CONVERT_FBX_CONVERT_H_
#define KOMA_CONVERT_FBX_CONVERT_H_

#include <cstdint>

#include "formats/fbx_scene.h"
#include "koma/v1/motion.pb.h"

namespace koma::convert {

// The take's models (names, parents) and their world positions at `frames` frames of the file's
// rate from the take's start (core/fbx_rig.h), frame_time 1 / fps. Evaluation polls the call's
// stop signal (core/stop_check.h): a stopped one leaves the positions unfinished.
v1::SkeletalMotion FbxMotion(const formats::FbxTakeRig& rig, int64_t frames);

}  // namespace koma::convert

#endif  // KOMA_CONVERT_FBX_CONVERT_H_

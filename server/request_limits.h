// Per-request limits the server enforces before doing any work. Each one is a server flag.
#ifndef KOMA_SERVER_REQUEST_LIMITS_H_
#define KOMA_SERVER_REQUEST_LIMITS_H_

#include <cstdint>

namespace koma::server {

struct RequestLimits {
  // Largest frames x values-per-frame in one request, where values-per-frame is the larger
  // of the channel count and 3 x joints. 20M covers a 100k-frame, 31-joint (96-channel) clip
  // with room to spare; memory per request is about 3 x 8 bytes per value.
  int64_t max_values = 20'000'000;
  // Largest skeleton, in joints.
  int32_t max_joints = 4096;
  // Largest file a request may carry (bvh_text, motion3_json, csv_text), in bytes. A file is
  // parsed whole into memory (about 8 bytes per number, ~1 to 3x the text), and what it
  // decodes to is then checked against max_values and max_joints as a decoded request is.
  int64_t max_file_bytes = 64 * 1024 * 1024;
  // Threads one RetimeSkeletal call's forward kinematics may use (a clip of at least
  // 2 x kFramesPerFkThread frames, core/forward_kinematics.h); 1 = the calling thread only.
  int threads_per_call = 1;
};

}  // namespace koma::server

#endif  // KOMA_SERVER_REQUEST_LIMITS_H_

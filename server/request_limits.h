// Per-request limits the server enforces before doing any work. Each one is a server flag.
#ifndef KOMA_SERVER_REQUEST_LIMITS_H_
#define KOMA_SERVER_REQUEST_LIMITS_H_

#include <cstdint>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"

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
  // LipBlink's recordings (LipBlinkRequest.audio, also within max_file_bytes): the longest
  // decoded, in seconds (the header's claim and the samples; memory grows with its film-grid
  // frames, CPU time with its samples), and the most channels.
  double max_audio_seconds = 7200.0;
  int max_audio_channels = 64;
  // Most samples one recording may decode (sample frames x channels), the decoding work.
  int64_t max_audio_samples = 1'000'000'000;
  // Most nodes a glTF file (RetimeSkeletalRequest.gltf) may have; the node tree is walked
  // every sampled frame, so this bounds the work per frame beside max_values.
  int64_t max_gltf_nodes = 65536;
  // Most animations a glTF file may have: each is sampled and retimed on its own, so the work
  // grows with their count beside their keys (max_values bounds the keys and the samples of
  // all of them together).
  int64_t max_gltf_animations = 4096;
  // Threads one RetimeSkeletal call's forward kinematics may use (a clip of at least
  // 2 x kFramesPerFkThread frames, core/forward_kinematics.h); 1 = the calling thread only.
  int threads_per_call = 1;
  // Longest one call may compute, in seconds, whatever its client's deadline (0: no bound).
  // The handlers' loops poll it (server/call_stop.h) and stop with DEADLINE_EXCEEDED.
  double max_call_seconds = 300.0;
  // LiveLipBlink (server/live_stream.h): streams at once; the longest audio one stream may
  // send, in seconds (a stream that never stops is ended, its frames answered first); the
  // largest audio message, bytes; the decided frames that may wait for a client that does not
  // read (10 s at 24 fps; gRPC's flow-control window holds some more before them); and the
  // longest a stream may go without a message, seconds.
  int live_max_streams = 1000;
  double live_max_seconds = 6 * 3600.0;
  int64_t live_max_message_bytes = 1 << 20;
  int live_max_queued_frames = 240;
  double live_idle_seconds = 30.0;
};

// With a film grid, the work is counted in grid frames: RESOURCE_EXHAUSTED when `grid_frames`
// x `per_frame` (`unit`: "curves", "values per frame") is over --max_values, naming the
// request part `subject` ("curves: 300 frames on the 24 fps grid (timing_fps) x 3 curves = 900
// exceeds the server limit --max_values=500"). One check for the three RPCs.
inline absl::Status CheckGridValues(absl::string_view subject, int64_t grid_frames,
                                    double timing_fps, int64_t per_frame, absl::string_view unit,
                                    const RequestLimits& limits) {
  const int64_t work = grid_frames * per_frame;
  if (work <= limits.max_values) return absl::OkStatus();
  return absl::ResourceExhaustedError(
      absl::StrCat(subject, ": ", grid_frames, " frames on the ", timing_fps,
                   " fps grid (timing_fps) x ", per_frame, " ", unit, " = ", work,
                   " exceeds the server limit --max_values=", limits.max_values));
}

}  // namespace koma::server

#endif  // KOMA_SERVER_REQUEST_LIMITS_H_

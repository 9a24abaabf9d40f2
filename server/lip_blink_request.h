// LipBlink: proto request -> validated core inputs -> mouth and eye conversion -> response.
#ifndef KOMA_SERVER_LIP_BLINK_REQUEST_H_
#define KOMA_SERVER_LIP_BLINK_REQUEST_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "core/lip_blink.h"
#include "core/voice_activity.h"
#include "koma/v1/retime.pb.h"
#include "server/request_limits.h"

namespace koma::server {

// The seed of an unseeded request: "koma" in ASCII.
inline constexpr uint64_t kDefaultLipBlinkSeed = 0x6b6f6d61;

struct LipBlinkJob {
  CurveSet set;
  std::vector<int> mouth_curves;  // indices into set.curves
  std::vector<int> eye_curves;
  MouthOptions mouth;
  EyeOptions eyes;
  uint64_t seed = kDefaultLipBlinkSeed;
  // The film grid holds are counted on; unset: source frames. With a grid, `mouth` and
  // `eyes` are for the grid's frames (intervals snapped, auto-blink fps = the grid's).
  std::optional<FilmGrid> grid;
  int grid_frames = 0;
  // A voice request (server/lip_blink_voice.h): the speech and the drawing each frame asks
  // for, on the frames holds count (grid frames, else source frames). The mouth curves'
  // inputs are then these drawings' levels, and their source values the closed level.
  std::optional<VoiceActivity> voice;
};

// Every field checked before any work; INVALID_ARGUMENT / RESOURCE_EXHAUSTED naming the
// field path ("mouth.mid_ratio", "eyes.auto_blink.hold", "mouth.ids[1]") and value.
absl::StatusOr<LipBlinkJob> ValidateLipBlinkRequest(const v1::LipBlinkRequest& request,
                                                    const RequestLimits& limits);

// Runs a validated job into `response` (mouths, eyes, curves, seed, timing_fps).
absl::Status RunLipBlinkJob(const LipBlinkJob& job, v1::LipBlinkResponse* response);

absl::Status HandleLipBlink(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                            v1::LipBlinkResponse* response);

}  // namespace koma::server

#endif  // KOMA_SERVER_LIP_BLINK_REQUEST_H_
